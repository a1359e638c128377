#pragma once
// A stored document (storage/document_codec.h StoredDocument, reached through the service headers) as served.
#include <functional>
#include <string>

#include "schema/json_io.h"
#include "services/jobs/job_types.h"

namespace anchordb::api {

// The JSON of an encoded document and the row it came from (for errors), e.g. a decoder and ToJson.
using DocumentJsonWriter = std::function<json::Json(const std::string& encoded, const std::string& what)>;

// An encoded document through `write`; the JSON text of a row written before its kind was typed (legacy_json, or
// JSON text in the document column: classifier and shape-model training jobs of schemas 24-26) as it was; a document
// that `write` cannot read (it throws Error) as {"unreadable": why}, so that one bad row does not hide others.
json::Json StoredDocumentJson(const services::JobDocument& document, const std::string& what, const DocumentJsonWriter& write);

}  // namespace anchordb::api
