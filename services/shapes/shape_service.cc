#include "services/shapes/shape_service.h"

#include <algorithm>
#include <chrono>
#include <set>

#include "engine/cloud/cloud_io.h"
#include "schema/error.h"
#include "schema/ids.h"
#include "storage/shape_documents.h"
#include "storage/shape_repository.h"

namespace anchordb::services {
namespace {

// engine::ShapeModelParams and its stored record (storage/shape_documents.h) have the same fields by name and type:
// one copy serves both directions.
template <typename To, typename From>
To CopyParams(const From& from) {
  To to;
  to.voxel_m = from.voxel_m;
  to.normal_radius_m = from.normal_radius_m;
  to.boundary_angle_rad = from.boundary_angle_rad;
  to.keypoint_spacing_m = from.keypoint_spacing_m;
  to.shot_radius_m = from.shot_radius_m;
  to.codebook_size = from.codebook_size;
  to.activated_words = from.activated_words;
  to.azimuth_bins = from.azimuth_bins;
  to.polar_bins = from.polar_bins;
  to.sphere_radius_m = from.sphere_radius_m;
  to.detection_spacing_m = from.detection_spacing_m;
  to.accept_fraction = from.accept_fraction;
  to.merge_distance_m = from.merge_distance_m;
  to.max_keypoints = from.max_keypoints;
  to.seed = from.seed;
  to.size_weight = from.size_weight;
  to.size_bandwidth = from.size_bandwidth;
  to.size_floor = from.size_floor;
  return to;
}

storage::ShapeModelReportRecord ReportRecord(const engine::TrainingReport& report, int mesh_views, double seconds) {
  storage::ShapeModelReportRecord r;
  for (std::size_t c = 0; c < report.categories.size(); ++c) {
    r.categories.push_back({report.categories[c], report.samples_per_category[c], report.keypoints_per_category[c]});
  }
  r.samples = report.samples;
  r.keypoints = report.keypoints;
  r.codebook_size = report.codebook_size;
  r.non_empty_bins = report.non_empty_bins;
  r.mesh_views = mesh_views;
  r.train_seconds = seconds;
  return r;
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
    const storage::ShapeTrainingRequestRecord r = storage::DecodeShapeTrainingRequest(s.request, "the training request");
    json::CheckId(r.options.name, "name");
    engine::CheckShapeModelParams(CopyParams<engine::ShapeModelParams>(r.options.params));
  };
  kind.run = [&store = store_, &clock = clock_, staging_area = staging_](JobContext& job) -> std::optional<std::string> {
    const storage::ShapeTrainingRequestRecord request = storage::DecodeShapeTrainingRequest(job.request(), "the training request");
    const std::string& name = request.options.name;
    Staged staged;
    {
      std::lock_guard<std::mutex> lock(staging_area->mutex);
      auto it = staging_area->staged.find(request.staging);
      if (it == staging_area->staged.end()) {
        throw Error(ErrorCode::kUnprocessable, "the training samples are gone (server restarted)", "samples");
      }
      staged = std::move(it->second);
      staging_area->staged.erase(it);
    }
    const engine::ShapeModelParams params = CopyParams<engine::ShapeModelParams>(request.options.params);
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
    storage::ShapeModelRecord stored;
    stored.name = name;
    stored.created_ns = clock.NowNs();
    stored.model = engine::EncodeShapeModel(model);
    stored.options.encoded = storage::EncodeShapeModelOptions(request.options);
    stored.report.encoded = storage::EncodeShapeModelReport(ReportRecord(report, staged.mesh_views, seconds));
    store.Write([&](storage::Connection& c) { storage::UpsertShapeModel(c, stored); });
    return storage::EncodeShapeTrainingResult({name, report.samples, report.keypoints, seconds});
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
  storage::ShapeTrainingRequestRecord request;
  request.options.name = r.name;
  request.options.params = CopyParams<storage::ShapeModelParamsRecord>(r.params);
  request.options.mesh_views = r.mesh_views;
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
      request.options.parts.push_back({field, s.category, false, static_cast<std::int64_t>(points.size())});
      staged.clouds.push_back({s.category, std::move(points)});
    } else {
      engine::TriangleMesh mesh;
      try {
        mesh = engine::ParseObj(s.body);
      } catch (const Error& e) {
        throw Error(e.code(), e.what(), field);
      }
      request.options.parts.push_back({field, s.category, true, static_cast<std::int64_t>(mesh.triangles.size())});
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
  request.staging = staging;
  try {
    return jobs_.Submit("shape_model_train", std::nullopt, storage::EncodeShapeTrainingRequest(request));
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
  v.options = r.options;
  v.report = r.report;
  if (!r.report.encoded.empty()) {
    try {
      for (const auto& c : storage::DecodeShapeModelReport(r.report.encoded, "shape model '" + r.name + "''s report").categories) {
        v.categories.push_back(c.category);
      }
    } catch (const Error&) {  // shown as unreadable where the report is written out
    }
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
