#pragma once
// Typed requests and results of 3D shape models (SPEC §4.7, thesis 4.1): training from labelled clouds (PCD / PLY)
// and meshes (OBJ, virtual scans from 12 views) as a job, stored models with their report, verification of a
// segment and detection in a scene.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "engine/shapes/shape_model.h"
#include "storage/document_codec.h"
#include "storage/shape_documents.h"

namespace anchordb::services {

enum class ShapeSampleKind { kCloud, kMesh };

// One training part as it arrived: a PCD / PLY cloud (any frame, metres) or an OBJ mesh (metres, z up).
struct ShapeSamplePart {
  std::string part;  // its name in the request (for errors)
  std::string category;
  ShapeSampleKind kind = ShapeSampleKind::kCloud;
  std::string body;
};

struct TrainShapeModelRequest {
  std::string name;  // an id; training again under a name replaces the stored model
  engine::ShapeModelParams params;
  std::vector<ShapeSamplePart> samples;
  std::vector<std::string> categories;  // optional: every one of them must have a sample
  int mesh_views = 12;                  // virtual scans per mesh, in [1, 72]
};

struct ShapeModelView {
  std::string name;
  std::int64_t created_ns = 0;
  std::vector<std::string> categories;
  // As stored (storage/shape_documents.h: the training options without the samples, the training report); a model
  // trained before schema 27 has JSON text there (StoredDocument::legacy_json).
  storage::StoredDocument options;
  storage::StoredDocument report;
};

struct ShapeClassification {
  engine::Verification verification;
  std::size_t points = 0;
};

struct ShapeDetections {
  std::vector<engine::ShapeDetection> detections;
  std::size_t points = 0;
};

}  // namespace anchordb::services
