#include "api/shape_json.h"

#include "api/shape_documents_json.h"
#include "api/stored_document_json.h"

namespace anchordb::api {
namespace {

Json Point(const Eigen::Vector3f& p) { return Json::array({p.x(), p.y(), p.z()}); }

engine::ShapeModelParams ParseParams(const Json& j) {
  engine::ShapeModelParams p;
  if (!j.is_object()) throw Error(ErrorCode::kInvalidArgument, "params is an object", "params");
  json::RejectUnknownKeys(j, {"voxel_m", "normal_radius_m", "boundary_angle_rad", "keypoint_spacing_m", "shot_radius_m",
                              "codebook_size", "activated_words", "azimuth_bins", "polar_bins", "sphere_radius_m",
                              "detection_spacing_m", "accept_fraction", "merge_distance_m", "max_keypoints", "seed"},
                          "params");
  const auto number = [&](const char* key, double& v) { v = json::FiniteNumberOr(j, key, v, "params"); };
  const auto integer = [&](const char* key, int& v) {
    const std::int64_t x = json::IntegerOr(j, key, v, "params");
    if (x < -1000000 || x > 1000000) throw Error(ErrorCode::kInvalidArgument, "out of range", std::string("params.") + key);
    v = static_cast<int>(x);
  };
  number("voxel_m", p.voxel_m);
  number("normal_radius_m", p.normal_radius_m);
  number("boundary_angle_rad", p.boundary_angle_rad);
  number("keypoint_spacing_m", p.keypoint_spacing_m);
  number("shot_radius_m", p.shot_radius_m);
  integer("codebook_size", p.codebook_size);
  integer("activated_words", p.activated_words);
  integer("azimuth_bins", p.azimuth_bins);
  integer("polar_bins", p.polar_bins);
  number("sphere_radius_m", p.sphere_radius_m);
  number("detection_spacing_m", p.detection_spacing_m);
  number("accept_fraction", p.accept_fraction);
  number("merge_distance_m", p.merge_distance_m);
  integer("max_keypoints", p.max_keypoints);
  const std::int64_t seed = json::IntegerOr(j, "seed", 1, "params");
  if (seed < 0) throw Error(ErrorCode::kInvalidArgument, "seed must be >= 0", "params.seed");
  p.seed = static_cast<std::uint64_t>(seed);
  return p;
}

}  // namespace

services::TrainShapeModelRequest ParseTrainShapeModelRequest(
    const Json& spec, const std::function<const std::string*(const std::string&)>& part_body) {
  json::RejectUnknownKeys(spec, {"name", "params", "mesh_views", "categories", "samples"});
  services::TrainShapeModelRequest r;
  r.name = json::RequireId(spec, "name");
  if (spec.contains("params")) r.params = ParseParams(spec["params"]);
  r.mesh_views = static_cast<int>(json::IntegerOr(spec, "mesh_views", 12));
  if (spec.contains("categories")) {
    const Json& c = spec["categories"];
    if (!c.is_array()) throw Error(ErrorCode::kInvalidArgument, "categories is an array of names", "categories");
    for (const Json& x : c) {
      if (!x.is_string()) throw Error(ErrorCode::kInvalidArgument, "categories is an array of names", "categories");
      r.categories.push_back(x.get<std::string>());
    }
  }
  const Json& samples = json::Require(spec, "samples");
  if (!samples.is_array() || samples.empty()) {
    throw Error(ErrorCode::kInvalidArgument, "samples is a non-empty array of {part, category, kind}", "samples");
  }
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const std::string path = "samples[" + std::to_string(i) + "]";
    const Json& s = samples[i];
    if (!s.is_object()) throw Error(ErrorCode::kInvalidArgument, "a sample is an object {part, category, kind}", path);
    json::RejectUnknownKeys(s, {"part", "category", "kind"}, path);
    services::ShapeSamplePart part;
    part.part = json::RequireString(s, "part", 128, path);
    part.category = json::RequireString(s, "category", 128, path);
    const std::string kind = json::RequireString(s, "kind", 16, path);
    if (kind == "cloud") {
      part.kind = services::ShapeSampleKind::kCloud;
    } else if (kind == "mesh") {
      part.kind = services::ShapeSampleKind::kMesh;
    } else {
      throw Error(ErrorCode::kInvalidArgument, "kind is cloud (PCD / PLY) or mesh (OBJ)", path + ".kind");
    }
    const std::string* body = part_body(part.part);
    if (!body) throw Error(ErrorCode::kInvalidArgument, "multipart part '" + part.part.substr(0, 64) + "' is missing", path + ".part");
    part.body = *body;
    r.samples.push_back(std::move(part));
  }
  return r;
}

Json ToJson(const services::ShapeModelView& v) {
  Json report = StoredDocumentJson(v.report, "shape model '" + v.name + "''s report", [](const std::string& d, const std::string& what) {
    return ToJson(storage::DecodeShapeModelReport(d, what));
  });
  Json options = StoredDocumentJson(v.options, "shape model '" + v.name + "''s options", [](const std::string& d, const std::string& what) {
    return ToJson(storage::DecodeShapeModelOptions(d, what));
  });
  // A model trained before schema 27: its categories as its JSON report has them.
  Json categories = v.categories;
  if (v.report.encoded.empty() && report.is_object() && report.contains("categories") && report["categories"].is_array()) {
    categories = Json::array();
    for (const auto& c : report["categories"]) categories.push_back(c.is_object() ? c.value("category", "") : "");
  }
  Json j = {{"name", v.name}, {"created_ns", v.created_ns}, {"categories", categories}};
  j["report"] = std::move(report);
  j["options"] = std::move(options);
  return j;
}

Json ToJson(const services::ShapeClassification& c) {
  Json scores = Json::array();
  for (const auto& s : c.verification.scores) {
    scores.push_back({{"category", s.category}, {"probability", s.probability}, {"weight", s.weight}});
  }
  Json j = {{"scores", scores}, {"centre_m", Point(c.verification.centre_m)}, {"keypoints", c.verification.keypoints},
            {"points", c.points}};
  j["category"] = c.verification.best.empty() ? Json(nullptr) : Json(c.verification.best);
  return j;
}

Json ToJson(const services::ShapeDetections& d) {
  Json list = Json::array();
  for (const auto& x : d.detections) {
    list.push_back({{"category", x.category}, {"centre_m", Point(x.centre_m)}, {"weight", x.weight},
                    {"relative_weight", x.relative_weight}, {"merged_spheres", x.merged_spheres}});
  }
  return {{"detections", list}, {"points", d.points}};
}

}  // namespace anchordb::api
