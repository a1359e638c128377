#pragma once
// Internal to storage/*.cc: the rows of a table of trained models (name, created_ns, model blob, options and report),
// shared by the classifiers (feature_repository.cc) and the shape models (shape_repository.cc). `table` is one of
// those compile-time table names, never input. Migration 0027: a row has its options and report as typed documents
// (options_document, report_document), or -- written before -- the JSON text of request_json / report_json.
#include <optional>
#include <string>
#include <vector>

#include "storage/blob_codec.h"
#include "storage/connection.h"
#include "storage/document_codec.h"

namespace anchordb::storage::trained_models {

template <typename Record>
void Upsert(Connection& c, const std::string& table, const Record& r) {
  Statement s(c, "INSERT INTO " + table + " (name, created_ns, model, request_json, report_json, options_document, "
                 "report_document) VALUES (?, ?, ?, '', '', ?, ?) "
                 "ON CONFLICT (name) DO UPDATE SET created_ns = excluded.created_ns, model = excluded.model, "
                 "request_json = '', report_json = '', options_document = excluded.options_document, "
                 "report_document = excluded.report_document");
  s.Bind(1, r.name).Bind(2, r.created_ns).BindBlob(3, EncodeBlob(BlobElement::kU8, {static_cast<std::uint32_t>(r.model.size())}, r.model));
  s.BindBlob(4, r.options.encoded).BindBlob(5, r.report.encoded);
  s.Run();
}

// Columns from `at`: request_json, report_json, options_document, report_document.
template <typename Record>
void ReadDocuments(const Statement& s, int at, Record& r) {
  r.options = s.IsNull(at + 2) ? StoredDocument{{}, s.Text(at)} : StoredDocument{s.Blob(at + 2), {}};
  r.report = s.IsNull(at + 3) ? StoredDocument{{}, s.Text(at + 1)} : StoredDocument{s.Blob(at + 3), {}};
}
constexpr const char* kDocumentColumns = "request_json, report_json, options_document, report_document";

template <typename Record>
std::optional<Record> Get(Connection& c, const std::string& table, const std::string& name, bool with_model) {
  Statement s(c, "SELECT name, created_ns, model, " + std::string(kDocumentColumns) + " FROM " + table + " WHERE name = ?");
  s.Bind(1, name);
  if (!s.Step()) return std::nullopt;
  Record r;
  r.name = s.Text(0);
  r.created_ns = s.Int(1);
  if (with_model) r.model = DecodeBlob(s.Blob(2)).bytes;
  ReadDocuments(s, 3, r);
  return r;
}

// Without the models, by name.
template <typename Record>
std::vector<Record> List(Connection& c, const std::string& table) {
  Statement s(c, "SELECT name, created_ns, " + std::string(kDocumentColumns) + " FROM " + table + " ORDER BY name");
  std::vector<Record> out;
  while (s.Step()) {
    Record r;
    r.name = s.Text(0);
    r.created_ns = s.Int(1);
    ReadDocuments(s, 2, r);
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace anchordb::storage::trained_models
