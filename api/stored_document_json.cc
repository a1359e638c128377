#include "api/stored_document_json.h"

#include "schema/error.h"

namespace anchordb::api {

json::Json StoredDocumentJson(const services::JobDocument& d, const std::string& what, const DocumentJsonWriter& write) {
  if (d.encoded.empty()) return json::Json::parse(d.legacy_json, nullptr, false);
  if (!storage::IsEncodedDocument(d.encoded)) return json::Json::parse(d.encoded, nullptr, false);
  try {
    return write(d.encoded, what);
  } catch (const Error& e) {
    return json::Json{{"unreadable", e.what()}};
  }
}

}  // namespace anchordb::api
