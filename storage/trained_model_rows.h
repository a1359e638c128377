#pragma once
// Internal to storage/*.cc: the rows of a table of trained models (name, created_ns, model blob, request_json,
// report_json), shared by the classifiers (feature_repository.cc) and the shape models (shape_repository.cc).
// `table` is one of those compile-time table names, never input.
#include <optional>
#include <string>
#include <vector>

#include "storage/blob_codec.h"
#include "storage/connection.h"

namespace anchordb::storage::trained_models {

template <typename Record>
void Upsert(Connection& c, const std::string& table, const Record& r) {
  Statement s(c, "INSERT INTO " + table + " (name, created_ns, model, request_json, report_json) VALUES (?, ?, ?, ?, ?) "
                 "ON CONFLICT (name) DO UPDATE SET created_ns = excluded.created_ns, model = excluded.model, "
                 "request_json = excluded.request_json, report_json = excluded.report_json");
  s.Bind(1, r.name).Bind(2, r.created_ns).BindBlob(3, EncodeBlob(BlobElement::kU8, {static_cast<std::uint32_t>(r.model.size())}, r.model));
  s.Bind(4, r.request_json).Bind(5, r.report_json);
  s.Run();
}

template <typename Record>
std::optional<Record> Get(Connection& c, const std::string& table, const std::string& name, bool with_model) {
  Statement s(c, "SELECT name, created_ns, model, request_json, report_json FROM " + table + " WHERE name = ?");
  s.Bind(1, name);
  if (!s.Step()) return std::nullopt;
  Record r;
  r.name = s.Text(0);
  r.created_ns = s.Int(1);
  if (with_model) r.model = DecodeBlob(s.Blob(2)).bytes;
  r.request_json = s.Text(3);
  r.report_json = s.Text(4);
  return r;
}

// Without the models, by name.
template <typename Record>
std::vector<Record> List(Connection& c, const std::string& table) {
  Statement s(c, "SELECT name, created_ns, request_json, report_json FROM " + table + " ORDER BY name");
  std::vector<Record> out;
  while (s.Step()) {
    Record r;
    r.name = s.Text(0);
    r.created_ns = s.Int(1);
    r.request_json = s.Text(2);
    r.report_json = s.Text(3);
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace anchordb::storage::trained_models
