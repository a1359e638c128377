#include "storage/shape_repository.h"

#include "storage/blob_codec.h"

namespace anchordb::storage {

void UpsertShapeModel(Connection& c, const ShapeModelRecord& r) {
  Statement s(c, "INSERT OR REPLACE INTO shape_models (name, created_ns, model, request_json, report_json) VALUES (?, ?, ?, ?, ?)");
  s.Bind(1, r.name).Bind(2, r.created_ns).BindBlob(3, EncodeBlob(BlobElement::kU8, {static_cast<std::uint32_t>(r.model.size())}, r.model));
  s.Bind(4, r.request_json).Bind(5, r.report_json);
  s.Run();
}

std::optional<ShapeModelRecord> GetShapeModel(Connection& c, const std::string& name, bool with_model) {
  Statement s(c, "SELECT name, created_ns, model, request_json, report_json FROM shape_models WHERE name = ?");
  s.Bind(1, name);
  if (!s.Step()) return std::nullopt;
  ShapeModelRecord r;
  r.name = s.Text(0);
  r.created_ns = s.Int(1);
  if (with_model) r.model = DecodeBlob(s.Blob(2)).bytes;
  r.request_json = s.Text(3);
  r.report_json = s.Text(4);
  return r;
}

std::vector<ShapeModelRecord> ListShapeModels(Connection& c) {
  Statement s(c, "SELECT name, created_ns, request_json, report_json FROM shape_models ORDER BY name");
  std::vector<ShapeModelRecord> out;
  while (s.Step()) {
    ShapeModelRecord r;
    r.name = s.Text(0);
    r.created_ns = s.Int(1);
    r.request_json = s.Text(2);
    r.report_json = s.Text(3);
    out.push_back(std::move(r));
  }
  return out;
}

bool DeleteShapeModel(Connection& c, const std::string& name) {
  Statement s(c, "DELETE FROM shape_models WHERE name = ?");
  s.Bind(1, name);
  s.Run();
  return c.Changes() > 0;
}

}  // namespace anchordb::storage
