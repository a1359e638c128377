#pragma once
// Rows of trained shape models (migrations/0013_shape_models.sql).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "storage/connection.h"
#include "storage/document_codec.h"

namespace anchordb::storage {

struct ShapeModelRecord {
  std::string name;
  std::int64_t created_ns = 0;
  std::string model;  // engine/shapes EncodeShapeModel bytes (empty when read without the model)
  // Encoded (storage/shape_documents.h: ShapeModelOptionsRecord / ShapeModelReportRecord); a row written before migration 0027
  // holds the JSON text an earlier version wrote instead (legacy_json), for the HTTP edge to show as it was.
  StoredDocument options;
  StoredDocument report;
};

void UpsertShapeModel(Connection& c, const ShapeModelRecord& r);
std::optional<ShapeModelRecord> GetShapeModel(Connection& c, const std::string& name, bool with_model);
std::vector<ShapeModelRecord> ListShapeModels(Connection& c);  // without models, by name
bool DeleteShapeModel(Connection& c, const std::string& name);

}  // namespace anchordb::storage
