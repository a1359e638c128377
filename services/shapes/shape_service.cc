#include "services/shapes/shape_service.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <set>

#include "engine/cloud/cloud_io.h"
#include "schema/error.h"
#include "schema/json_io.h"
#include "storage/shape_repository.h"

namespace anchordb::services {
namespace {

using Json = nlohmann::json;

Json ParamsJson(const engine::ShapeModelParams& p) {
  return {{"voxel_m", p.voxel_m}, {"normal_radius_m", p.normal_radius_m}, {"boundary_angle_rad", p.boundary_angle_rad},
          {"keypoint_spacing_m", p.keypoint_spacing_m}, {"shot_radius_m", p.shot_radius_m},
          {"codebook_size", p.codebook_size}, {"activated_words", p.activated_words}, {"azimuth_bins", p.azimuth_bins},
          {"polar_bins", p.polar_bins}, {"sphere_radius_m", p.sphere_radius_m},
          {"detection_spacing_m", p.detection_spacing_m}, {"accept_fraction", p.accept_fraction},
          {"merge_distance_m", p.merge_distance_m}, {"max_keypoints", p.max_keypoints}, {"seed", p.seed}};
}

std::vector<Eigen::Vector3f> DecodePoints(const std::string& body, std::size_t max_points, const std::string& field) {
  if (body.empty()) throw Error(ErrorCode::kUnprocessable, "the cloud is empty", field);
  engine::DecodedCloud cloud;
  try {
    cloud = engine::DecodeCloud(body, max_points);
  } catch (const Error& e) {
    throw Error(e.code(), e.what(), field);
  }
  if (cloud.points.empty()) throw Error(ErrorCode::kUnprocessable, "the cloud has no points", field);
  for (std::size_t i = 0; i < cloud.points.size(); ++i) {
    if (!cloud.points[i].allFinite()) {
      throw Error(ErrorCode::kUnprocessable, "point " + std::to_string(i) + " is not finite (NaN or infinite)", field);
    }
  }
  return std::move(cloud.points);
}

}  // namespace

ShapeService::ShapeService(storage::Store& store, JobService& jobs, ShapeSettings settings, const Clock& clock)
    : store_(store), jobs_(jobs), settings_(settings), clock_(clock) {
  JobKind kind;
  kind.name = "shape_model_train";
  kind.first_stage = "scanning";
  kind.check = [](const JobSubmission& s) {
    const Json j = Json::parse(s.request);
    json::CheckId(j.at("name").get<std::string>(), "name");
  };
  kind.run = [&store = store_, &clock = clock_, staging_area = staging_](JobContext& job) -> std::optional<std::string> {
    const Json request = Json::parse(job.request());
    const std::string name = request.at("name").get<std::string>();
    Staged staged;
    {
      std::lock_guard<std::mutex> lock(staging_area->mutex);
      auto it = staging_area->staged.find(request.at("staging").get<std::int64_t>());
      if (it == staging_area->staged.end()) {
        throw Error(ErrorCode::kUnprocessable, "the training samples are gone (server restarted)", "samples");
      }
      staged = std::move(it->second);
      staging_area->staged.erase(it);
    }
    engine::ShapeModelParams params = engine::ShapeModelParams{};
    const Json& p = request.at("params");
    params.voxel_m = p.at("voxel_m");
    params.normal_radius_m = p.at("normal_radius_m");
    params.boundary_angle_rad = p.at("boundary_angle_rad");
    params.keypoint_spacing_m = p.at("keypoint_spacing_m");
    params.shot_radius_m = p.at("shot_radius_m");
    params.codebook_size = p.at("codebook_size");
    params.activated_words = p.at("activated_words");
    params.azimuth_bins = p.at("azimuth_bins");
    params.polar_bins = p.at("polar_bins");
    params.sphere_radius_m = p.at("sphere_radius_m");
    params.detection_spacing_m = p.at("detection_spacing_m");
    params.accept_fraction = p.at("accept_fraction");
    params.merge_distance_m = p.at("merge_distance_m");
    params.max_keypoints = p.at("max_keypoints");
    params.seed = p.at("seed");
    const auto start = std::chrono::steady_clock::now();
    std::vector<engine::LabelledCloud> samples = std::move(staged.clouds);
    for (std::size_t m = 0; m < staged.meshes.size(); ++m) {
      job.Progress("scanning", 0.2 * m / staged.meshes.size());
      for (auto& scan : engine::VirtualScans(staged.meshes[m].second, staged.mesh_views, engine::ScanCamera{})) {
        if (scan.size() >= 10) samples.push_back({staged.meshes[m].first, std::move(scan)});
      }
    }
    engine::TrainingReport report;
    const engine::ShapeModel model = engine::TrainShapeModel(samples, params, [&](double fraction, const std::string& stage) {
      job.Progress(stage, 0.2 + 0.8 * fraction);  // throws once cancelled
      return true;
    }, &report);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    Json per_category = Json::array();
    for (std::size_t c = 0; c < report.categories.size(); ++c) {
      per_category.push_back({{"category", report.categories[c]}, {"samples", report.samples_per_category[c]},
                              {"keypoints", report.keypoints_per_category[c]}});
    }
    const Json report_json = {{"categories", per_category}, {"samples", report.samples}, {"keypoints", report.keypoints},
                              {"codebook_size", report.codebook_size}, {"non_empty_bins", report.non_empty_bins},
                              {"mesh_views", staged.mesh_views}, {"train_seconds", seconds}};
    Json options = request;
    options.erase("staging");
    store.Write([&](storage::Connection& c) {
      storage::UpsertShapeModel(c, {name, clock.NowNs(), engine::EncodeShapeModel(model), options.dump(), report_json.dump()});
    });
    return Json{{"name", name}, {"samples", report.samples}, {"keypoints", report.keypoints}, {"train_seconds", seconds}}.dump();
  };
  jobs_.Register(std::move(kind));
}

JobTicket ShapeService::SubmitTraining(const TrainShapeModelRequest& r) {
  json::CheckId(r.name, "name");
  engine::CheckShapeModelParams(r.params);
  if (r.samples.empty()) throw Error(ErrorCode::kInvalidArgument, "no samples", "samples");
  if (r.samples.size() > settings_.max_samples) {
    throw Error(ErrorCode::kPayloadTooLarge, "at most " + std::to_string(settings_.max_samples) + " samples", "samples");
  }
  if (r.mesh_views < 1 || r.mesh_views > 72) throw Error(ErrorCode::kInvalidArgument, "mesh_views must be in [1, 72]", "mesh_views");
  Staged staged;
  staged.mesh_views = r.mesh_views;
  Json parts = Json::array();
  std::set<std::string> with_samples;
  for (std::size_t i = 0; i < r.samples.size(); ++i) {
    const auto& s = r.samples[i];
    const std::string field = s.part.empty() ? "samples[" + std::to_string(i) + "]" : s.part;
    if (s.category.empty() || s.category.size() > 128) {
      throw Error(ErrorCode::kInvalidArgument, "a category of 1 to 128 characters", field + ".category");
    }
    if (s.kind == ShapeSampleKind::kCloud) {
      auto points = DecodePoints(s.body, settings_.max_points, field);
      if (points.size() < 10) throw Error(ErrorCode::kUnprocessable, "a training cloud needs at least 10 points", field);
      parts.push_back({{"part", field}, {"category", s.category}, {"kind", "cloud"}, {"points", points.size()}});
      staged.clouds.push_back({s.category, std::move(points)});
    } else {
      engine::TriangleMesh mesh;
      try {
        mesh = engine::ParseObj(s.body);
      } catch (const Error& e) {
        throw Error(e.code(), e.what(), field);
      }
      parts.push_back({{"part", field}, {"category", s.category}, {"kind", "mesh"}, {"triangles", mesh.triangles.size()}});
      staged.meshes.emplace_back(s.category, std::move(mesh));
    }
    with_samples.insert(s.category);
  }
  for (const auto& c : r.categories) {
    if (!with_samples.count(c)) throw Error(ErrorCode::kUnprocessable, "category '" + c.substr(0, 64) + "' has no samples", "categories");
  }
  std::int64_t staging = 0;
  {
    std::lock_guard<std::mutex> lock(staging_->mutex);
    staging = staging_->next++;
    staging_->staged[staging] = std::move(staged);
  }
  const Json request = {{"name", r.name}, {"params", ParamsJson(r.params)}, {"mesh_views", r.mesh_views},
                        {"parts", parts}, {"staging", staging}};
  try {
    return jobs_.Submit("shape_model_train", std::nullopt, request.dump());
  } catch (...) {
    std::lock_guard<std::mutex> lock(staging_->mutex);
    staging_->staged.erase(staging);
    throw;
  }
}

namespace {

ShapeModelView ViewOf(const storage::ShapeModelRecord& r) {
  ShapeModelView v;
  v.name = r.name;
  v.created_ns = r.created_ns;
  v.report_json = r.report_json;
  v.request_json = r.request_json;
  const Json report = Json::parse(r.report_json, nullptr, false);
  if (report.is_object() && report.contains("categories")) {
    for (const auto& c : report["categories"]) v.categories.push_back(c.value("category", ""));
  }
  return v;
}

}  // namespace

std::vector<ShapeModelView> ShapeService::List() {
  std::vector<ShapeModelView> out;
  for (const auto& r : store_.Read([](storage::Connection& c) { return storage::ListShapeModels(c); })) out.push_back(ViewOf(r));
  return out;
}

ShapeModelView ShapeService::Get(const std::string& name) {
  const auto r = store_.Read([&](storage::Connection& c) { return storage::GetShapeModel(c, name, false); });
  if (!r) throw Error(ErrorCode::kNotFound, "shape model '" + name.substr(0, 64) + "' does not exist", "name");
  return ViewOf(*r);
}

void ShapeService::Delete(const std::string& name) {
  const bool gone = store_.Write([&](storage::Connection& c) { return storage::DeleteShapeModel(c, name); });
  if (!gone) throw Error(ErrorCode::kNotFound, "shape model '" + name.substr(0, 64) + "' does not exist", "name");
  std::lock_guard<std::mutex> lock(mutex_);
  cache_.erase(name);
}

std::shared_ptr<const engine::ShapeModel> ShapeService::Model(const std::string& name) {
  const auto r = store_.Read([&](storage::Connection& c) { return storage::GetShapeModel(c, name, true); });
  if (!r) throw Error(ErrorCode::kNotFound, "shape model '" + name.substr(0, 64) + "' does not exist", "name");
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = cache_.find(name);
  if (it != cache_.end() && it->second.first == r->created_ns) return it->second.second;
  auto model = std::make_shared<const engine::ShapeModel>(engine::DecodeShapeModel(r->model));
  cache_[name] = {r->created_ns, model};
  return model;
}

std::shared_ptr<const engine::ShapeModel> ShapeService::Find(const std::string& name) {
  try {
    return Model(name);
  } catch (const Error& e) {
    if (e.code() == ErrorCode::kNotFound) return nullptr;
    throw;
  }
}

std::optional<std::string> ShapeService::Newest() {
  std::optional<std::string> name;
  std::int64_t newest = 0;
  for (const auto& r : store_.Read([](storage::Connection& c) { return storage::ListShapeModels(c); })) {
    if (!name || r.created_ns > newest) name = r.name, newest = r.created_ns;
  }
  return name;
}

std::vector<Eigen::Vector3f> ShapeService::DecodeQuery(const std::string& body) const {
  return DecodePoints(body, settings_.max_points, "body");
}

ShapeClassification ShapeService::Classify(const std::string& name, const std::string& body) {
  const auto model = Model(name);
  const auto points = DecodeQuery(body);
  return {engine::Verify(*model, points), points.size()};
}

ShapeDetections ShapeService::Detect(const std::string& name, const std::string& body) {
  const auto model = Model(name);
  const auto points = DecodeQuery(body);
  return {engine::Detect(*model, points), points.size()};
}

}  // namespace anchordb::services
