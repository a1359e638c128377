#include "storage/shape_repository.h"

#include "storage/trained_model_rows.h"

namespace anchordb::storage {

void UpsertShapeModel(Connection& c, const ShapeModelRecord& r) { trained_models::Upsert(c, "shape_models", r); }

std::optional<ShapeModelRecord> GetShapeModel(Connection& c, const std::string& name, bool with_model) {
  return trained_models::Get<ShapeModelRecord>(c, "shape_models", name, with_model);
}

std::vector<ShapeModelRecord> ListShapeModels(Connection& c) {
  return trained_models::List<ShapeModelRecord>(c, "shape_models");
}

bool DeleteShapeModel(Connection& c, const std::string& name) {
  Statement s(c, "DELETE FROM shape_models WHERE name = ?");
  s.Bind(1, name);
  s.Run();
  return c.Changes() > 0;
}

}  // namespace anchordb::storage
