#include "services/segmentation/furniture_segmentation_service.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>

#include "engine/scene/projection.h"
#include "engine/segmentation/footprint.h"
#include "engine/segmentation/geometric_categories.h"
#include "engine/segmentation/segment_decisions.h"
#include "schema/error.h"
#include "services/common/cloud_bytes.h"
#include "services/common/require.h"
#include "services/scene/keyframe_listener.h"
#include "storage/blob_codec.h"
#include "storage/event_repository.h"
#include "storage/furniture_instance_repository.h"

namespace anchordb::services {

namespace {
namespace seg = engine::segmentation;

std::string EncodeCloudBlob(const std::vector<Eigen::Vector3f>& points) {
  std::vector<float> flat;
  flat.reserve(points.size() * 3);
  for (const auto& p : points) flat.insert(flat.end(), {p.x(), p.y(), p.z()});
  return storage::EncodeBlob(storage::BlobElement::kF32, {static_cast<std::uint32_t>(points.size()), 3}, storage::AsBytes(flat), 1);
}

std::vector<Eigen::Vector3f> DecodeCloudBlob(const std::string& blob) {
  std::vector<Eigen::Vector3f> out;
  if (blob.empty()) return out;
  const std::optional<std::vector<float>> xyz = storage::DecodeArray<float>(blob, storage::BlobElement::kF32);
  if (!xyz || xyz->size() % 3 != 0) throw Error(ErrorCode::kInternal, "a stored furniture cloud does not decode");
  for (std::size_t i = 0; i + 2 < xyz->size(); i += 3) out.emplace_back((*xyz)[i], (*xyz)[i + 1], (*xyz)[i + 2]);
  return out;
}

bool IsPerceived(const storage::InstanceRecord& r, const std::set<std::int64_t>& perceived) { return perceived.count(r.id) > 0; }

seg::Footprint FootprintOfInstance(const storage::InstanceRecord& r) {
  seg::Footprint f;
  f.centre_m = Eigen::Vector2d(r.position[0], r.position[1]);
  f.extent_m = Eigen::Vector2d(r.extent[0], r.extent[1]);
  f.yaw_rad = r.yaw_rad;
  return f;
}

FurnitureInstanceView ViewOf(const storage::InstanceRecord& r, const std::optional<storage::FurnitureInstanceRecord>& f) {
  FurnitureInstanceView v;
  v.id = r.id;
  v.perceived = f.has_value();
  double sum = 0.0;
  for (const auto& [k, w] : r.labels) v.categories.push_back({k, w}), sum += w;
  for (auto& c : v.categories) c.probability = sum > 0 ? c.probability / sum : 0.0;
  std::stable_sort(v.categories.begin(), v.categories.end(), [](const CategoryShare& a, const CategoryShare& b) { return a.probability > b.probability; });
  if (!v.categories.empty()) v.label = v.categories.front().category, v.label_probability = v.categories.front().probability;
  v.position_m = Eigen::Vector2d(r.position[0], r.position[1]);
  v.extent_m = Eigen::Vector2d(r.extent[0], r.extent[1]);
  v.yaw_rad = r.yaw_rad;
  v.updated_ns = r.updated_ns;
  if (f) {
    v.min_z_m = f->min_z_m;
    v.height_m = f->height_m;
    v.classifier = f->classifier;
    v.evidence = f->evidence_keyframes;
    v.observations = f->observations;
  } else {
    v.min_z_m = r.position[2] - 0.5 * r.extent[2];
    v.height_m = r.extent[2];
    v.classifier = "operator";
  }
  return v;
}

// p(f) over the knowledge's categories: the shape prior, times the shape model's verification when there is one
// (engine/segmentation/segment_decisions.h).
std::vector<double> Classify(const seg::FurnitureSegment& s, std::optional<double> floor_z_m, const std::vector<std::string>& ids,
                             const engine::ShapeModel* model) {
  std::vector<double> p = seg::GeometricCategories(seg::MeasureSegment(s, floor_z_m), ids);
  if (!model) return p;
  return seg::PriorTimesVerification(std::move(p), ids, VerifySegment(*model, s.points_m));
}

}  // namespace

SegmentationOutcome RunSegmentation(const FurnitureSegmentationService::Core& core, const std::string& map,
                                    const SegmentationRequest& r, std::optional<std::int64_t> job_id,
                                    const std::vector<Eigen::Vector3f>* client_cloud);

FurnitureSegmentationService::FurnitureSegmentationService(storage::Store& store, JobService& jobs, std::vector<std::string> category_ids,
                                                           const Clock& clock, SegmentationLinks links, SegmentationSettings settings)
    : store_(store), jobs_(jobs),
      core_(std::make_shared<Core>(Core{store, std::move(category_ids), clock, std::move(links), settings})) {
  JobKind kind;
  kind.name = "furniture_segment";
  kind.first_stage = "reading";
  kind.needs_map = true;
  kind.check = [](const JobSubmission& s) { CheckSegmentationRequest(SegmentationRequestFromDocument(s.request)); };
  // Captures the shared core, not the service: the job service may still run this while the capabilities are
  // destroyed.
  kind.run = [core = core_](JobContext& job) -> std::optional<std::string> {
    job.Progress("segmenting", 0.1);
    std::optional<std::int64_t> staging;
    SegmentationRequest request = SegmentationRequestFromDocument(job.request(), &staging);
    std::vector<Eigen::Vector3f> staged;
    if (request.source == SegmentationSource::kCloud) {
      std::lock_guard<std::mutex> lock(core->staging->mutex);
      const auto it = staging ? core->staging->clouds.find(*staging) : core->staging->clouds.end();
      if (it == core->staging->clouds.end()) {
        throw Error(ErrorCode::kUnprocessable, "the room cloud of this job is gone (the server restarted); send it again", "body");
      }
      staged = std::move(it->second);
      core->staging->clouds.erase(it);
    }
    const SegmentationOutcome out = RunSegmentation(*core, *job.map(), request, job.id(), &staged);
    return SegmentationResultDocument(out, *job.map());
  };
  jobs_.Register(std::move(kind));
}

JobTicket FurnitureSegmentationService::Submit(const std::string& map, const SegmentationRequest& request) {
  CheckSegmentationRequest(request);
  if (request.shape_model && (!core_->links.shape_model || !core_->links.shape_model(*request.shape_model))) {
    throw Error(ErrorCode::kNotFound, "shape model '" + *request.shape_model + "' does not exist", "shape_model");
  }
  if (request.source == SegmentationSource::kOctomap && !core_->links.octomap) {
    throw Error(ErrorCode::kUnprocessable, "this server has no OctoMap capability; use source keyframes or cloud", "source");
  }
  if (request.source != SegmentationSource::kCloud) return jobs_.Submit("furniture_segment", map, SegmentationRequestDocument(request));
  std::vector<Eigen::Vector3f> cloud = DecodeRoomCloud(request.cloud_bytes, request.skip_nonfinite, core_->settings.max_cloud_points);
  std::int64_t staging = 0;
  {
    std::lock_guard<std::mutex> lock(core_->staging->mutex);
    staging = core_->staging->next++;
    core_->staging->clouds[staging] = std::move(cloud);
  }
  try {
    return jobs_.Submit("furniture_segment", map, SegmentationRequestDocument(request, staging));
  } catch (...) {
    std::lock_guard<std::mutex> lock(core_->staging->mutex);
    core_->staging->clouds.erase(staging);
    throw;
  }
}

SegmentationOutcome FurnitureSegmentationService::Run(const std::string& map, const SegmentationRequest& r, std::optional<std::int64_t> job_id) {
  std::vector<Eigen::Vector3f> cloud;
  if (r.source == SegmentationSource::kCloud) cloud = DecodeRoomCloud(r.cloud_bytes, r.skip_nonfinite, core_->settings.max_cloud_points);
  return RunSegmentation(*core_, map, r, job_id, &cloud);
}

namespace {

// The shape model a segmentation classifies with: the one named, else the newest stored when asked for, else none
// (by shape alone; also when the newest was deleted meanwhile). Sets `name` to the model's name or nothing.
std::shared_ptr<const engine::ShapeModel> ShapeModelOf(const SegmentationLinks& links, const SegmentationRequest& r,
                                                       std::optional<std::string>& name) {
  std::shared_ptr<const engine::ShapeModel> model;
  name = r.shape_model;
  if (!name && r.use_stored_shape_model && links.newest_shape_model) name = links.newest_shape_model();
  if (name) {
    if (links.shape_model) model = links.shape_model(*name);
    if (!model && r.shape_model) throw Error(ErrorCode::kNotFound, "shape model '" + *r.shape_model + "' does not exist", "shape_model");
    if (!model) name.reset();
  }
  return model;
}

// The room cloud of keyframes and the cameras that took them (empty for the other sources). Checks the map.
struct RoomCloud {
  std::vector<seg::KeyframeView> cameras;
  std::vector<Eigen::Vector3f> points_m;
};

RoomCloud ReadKeyframeCloud(storage::Connection& c, const std::string& map, const SegmentationRequest& r) {
  RequireMap(c, map);
  RoomCloud out;
  if (r.source != SegmentationSource::kKeyframes) return out;
  const std::vector<std::int64_t> ids = r.keyframes.empty() ? storage::NewestKeyframeIds(c, map, r.max_keyframes) : r.keyframes;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    std::optional<KeyframeNotice> kf = LoadKeyframeNotice(c, map, ids[i]);
    if (!kf) throw Error(ErrorCode::kNotFound, "keyframe " + std::to_string(ids[i]) + " does not exist in map '" + map + "'", "keyframes[" + std::to_string(i) + "]");
    // By default only the keyframes that open and close an observation: between them a person may stand in
    // the view long enough to enter the static background.
    if (r.keyframes.empty() && kf->kind != "begin" && kf->kind != "end") continue;
    // The keyframe's own depth, not its model's static background: a person who stood still in the view may
    // linger in the background after leaving.
    std::vector<std::uint16_t> depth = kf->depth_mm;
    const double max_mm = r.max_range_m * 1000.0;
    for (auto& d : depth) {
      if (d > max_mm) d = 0;
    }
    const auto points = engine::BackProjectRaw(depth, 1000.0, kf->K, kf->X_MapCamera);
    out.points_m.insert(out.points_m.end(), points.begin(), points.end());
    out.cameras.push_back({kf->keyframe_id, kf->K, kf->X_MapCamera, std::move(depth)});
  }
  return out;
}

// The room cloud of the request's source into `room` (the OctoMap's occupied voxels, the client's cloud, or the
// keyframes' read before); out.source and out.octomap_truncated set. Answers the parameters for that cloud (an
// OctoMap's resolution sets its own).
seg::SegmentationParams TakeSourceCloud(const SegmentationLinks& links, const std::string& map, const SegmentationRequest& r,
                                        const std::vector<Eigen::Vector3f>* client_cloud, RoomCloud& room,
                                        SegmentationOutcome& out) {
  if (r.source == SegmentationSource::kOctomap) {
    out.source = "octomap";
    std::optional<OccupiedCloud> tree = links.octomap ? links.octomap(map) : std::nullopt;
    if (!links.octomap) throw Error(ErrorCode::kUnprocessable, "this server has no OctoMap capability", "source");
    if (!tree) throw Error(ErrorCode::kNotFound, "map '" + map + "' has no OctoMap", "octomap");
    if (tree->points_m.empty()) throw Error(ErrorCode::kUnprocessable, "the OctoMap of map '" + map + "' has no occupied voxel", "octomap");
    room.points_m = std::move(tree->points_m);
    out.octomap_truncated = tree->truncated;
    return seg::ParamsForVoxelCentres(r.params, tree->resolution_m);
  }
  if (r.source == SegmentationSource::kCloud) {
    out.source = "cloud";
    if (!client_cloud || client_cloud->empty()) throw Error(ErrorCode::kUnprocessable, "the room cloud is empty", "body");
    room.points_m = *client_cloud;
    return r.params;
  }
  out.source = "keyframes";
  if (room.points_m.empty()) throw Error(ErrorCode::kUnprocessable, "the room cloud is empty (no keyframe, or no depth within max_range_m)", "keyframes");
  return r.params;
}

void Summarise(const seg::SegmentationResult& result, SegmentationOutcome& out) {
  out.bridges_cut = result.bridges_cut;
  out.input_points = result.input_points;
  out.thinned_points = result.thinned_points;
  out.remaining_points = result.remaining_points;
  for (const auto& p : result.planes) out.planes.push_back(seg::PlaneRoleName(p.role));
  out.small_clusters = result.small_clusters;
  out.flying_dropped = result.flying_dropped;
  out.floor_z_m = result.floor_z_m;
}

// A segment's category shares (in the order of the category ids) and the keyframes that saw it.
struct SegmentClasses {
  std::vector<double> p;
  std::vector<std::int64_t> evidence;
};

// What writing one segmentation's instances needs besides the segments.
struct InstanceWrite {
  const std::string& map;
  const SegmentationRequest& r;
  const std::vector<std::string>& category_ids;
  const std::string& classifier;  // geometry | shape_model:<name>
  std::optional<std::int64_t> job_id;
  std::int64_t now_ns;
};

// One segment as an instance: an operator's furniture it overlaps (IoU >= match_iou) is kept as it is; a perceived
// one is updated (category shares averaged over its observations, evidence joined); else a new instance. `known` and
// `perceived` grow with the instances created.
SegmentOutcome WriteSegment(storage::Connection& c, const InstanceWrite& w, const seg::FurnitureSegment& s,
                            const SegmentClasses& classes, std::vector<storage::InstanceRecord>& known,
                            std::set<std::int64_t>& perceived) {
  std::vector<seg::Footprint> footprints;
  std::vector<bool> is_perceived;
  for (const auto& k : known) footprints.push_back(FootprintOfInstance(k)), is_perceived.push_back(IsPerceived(k, perceived));
  const seg::SegmentMatchResult match = seg::MatchSegment(s.footprint, footprints, is_perceived, w.r.match_iou);
  SegmentOutcome o;
  if (match.match == seg::SegmentMatch::kKeepOperatorPiece) {
    o.action = "kept_operator";
    o.instance = ViewOf(known[match.index], std::nullopt);
    return o;
  }
  storage::InstanceRecord inst;
  storage::FurnitureInstanceRecord fr;
  std::map<std::string, double> labels;
  std::set<std::int64_t> evidence(classes.evidence.begin(), classes.evidence.end());
  const bool update = match.match == seg::SegmentMatch::kUpdatePerceivedPiece;
  if (update) {
    inst = known[match.index];
    fr = *storage::FindFurnitureInstance(c, w.map, inst.id, false);
    evidence.insert(fr.evidence_keyframes.begin(), fr.evidence_keyframes.end());
    labels = seg::AverageCategoryShares(inst.labels, static_cast<double>(fr.observations), w.category_ids, classes.p);
    fr.observations += 1;
  } else {
    inst.map_id = w.map;
    inst.kind = "furniture";
    inst.created_ns = w.now_ns;
    for (std::size_t i = 0; i < w.category_ids.size(); ++i) labels[w.category_ids[i]] = classes.p[i];
    fr.created_ns = w.now_ns;
    fr.observations = 1;
  }
  inst.labels = labels;
  inst.label_locked = false;
  inst.status = "present";
  inst.position[0] = s.footprint.centre_m.x();
  inst.position[1] = s.footprint.centre_m.y();
  inst.position[2] = 0.5 * (s.footprint.min_z_m + s.footprint.max_z_m);
  inst.extent[0] = s.footprint.extent_m.x();
  inst.extent[1] = s.footprint.extent_m.y();
  inst.extent[2] = s.footprint.height_m();
  inst.yaw_rad = s.footprint.yaw_rad;
  inst.last_seen_ns = w.now_ns;
  inst.updated_ns = w.now_ns;
  if (update) {
    storage::UpdateInstance(c, inst);
  } else {
    inst.id = storage::InsertInstance(c, inst);
    storage::AppendHistory(c, {inst.id, 0, w.now_ns, true, {inst.position[0], inst.position[1], inst.position[2]}, std::nullopt});
    known.push_back(inst);
    perceived.insert(inst.id);
  }
  fr.instance_id = inst.id;
  fr.map_id = w.map;
  fr.classifier = w.classifier;
  fr.min_z_m = s.footprint.min_z_m;
  fr.height_m = s.footprint.height_m();
  fr.evidence_keyframes.assign(evidence.begin(), evidence.end());
  fr.job_id = w.job_id;
  fr.cloud = EncodeCloudBlob(s.points_m);
  fr.updated_ns = w.now_ns;
  storage::UpsertFurnitureInstance(c, fr);
  o.action = update ? "updated" : "created";
  o.instance = ViewOf(inst, fr);
  o.instance.points = static_cast<std::int64_t>(s.points_m.size());
  return o;
}

}  // namespace

SegmentationOutcome RunSegmentation(const FurnitureSegmentationService::Core& core, const std::string& map,
                                    const SegmentationRequest& r, std::optional<std::int64_t> job_id,
                                    const std::vector<Eigen::Vector3f>* client_cloud) {
  CheckSegmentationRequest(r);
  SegmentationOutcome out;
  const std::shared_ptr<const engine::ShapeModel> model = ShapeModelOf(core.links, r, out.shape_model);
  // 1. The room cloud.
  RoomCloud room = core.store.Read([&](storage::Connection& c) { return ReadKeyframeCloud(c, map, r); });
  const seg::SegmentationParams params = TakeSourceCloud(core.links, map, r, client_cloud, room, out);
  // 2. Segments (outside any transaction).
  const auto t0 = std::chrono::steady_clock::now();
  const seg::SegmentationResult result = seg::SegmentFurniture(room.points_m, params);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  Summarise(result, out);
  std::vector<SegmentClasses> classes;
  for (const seg::FurnitureSegment& s : result.segments) {
    classes.push_back({Classify(s, result.floor_z_m, core.category_ids, model.get()), seg::SegmentEvidence(s.points_m, room.cameras, r.max_range_m)});
  }
  const std::string classifier = model ? "shape_model:" + *out.shape_model : "geometry";
  // 3. Instances, in one write.
  const InstanceWrite write{map, r, core.category_ids, classifier, job_id, core.clock.NowNs()};
  core.store.Write([&](storage::Connection& c) {
    RequireMap(c, map);
    storage::InstanceFilter f;
    f.kind = "furniture";
    f.limit = 100000;
    std::vector<storage::InstanceRecord> known = storage::ListInstances(c, map, f, false);
    std::set<std::int64_t> perceived;
    for (const auto& fr : storage::ListFurnitureInstances(c, map, false)) perceived.insert(fr.instance_id);
    for (std::size_t k = 0; k < result.segments.size(); ++k) {
      out.segments.push_back(WriteSegment(c, write, result.segments[k], classes[k], known, perceived));
    }
  });
  return out;
}

std::vector<FurnitureInstanceView> FurnitureSegmentationService::List(const std::string& map) {
  return store_.Read([&](storage::Connection& c) {
    RequireMap(c, map);
    storage::InstanceFilter f;
    f.kind = "furniture";
    f.limit = 100000;
    std::map<std::int64_t, storage::FurnitureInstanceRecord> rows;
    for (auto& fr : storage::ListFurnitureInstances(c, map, true)) rows[fr.instance_id] = std::move(fr);
    std::vector<FurnitureInstanceView> out;
    for (const auto& r : storage::ListInstances(c, map, f, false)) {
      const auto it = rows.find(r.id);
      out.push_back(ViewOf(r, it == rows.end() ? std::nullopt : std::optional(it->second)));
      if (it != rows.end()) out.back().points = static_cast<std::int64_t>(DecodeCloudBlob(it->second.cloud).size());
    }
    return out;
  });
}

FurnitureInstanceView FurnitureSegmentationService::Get(const std::string& map, std::int64_t id) {
  return store_.Read([&](storage::Connection& c) {
    RequireMap(c, map);
    const auto r = storage::FindInstance(c, map, id, false);
    if (!r || r->kind != "furniture" || r->status == "deleted") {
      throw Error(ErrorCode::kNotFound, "furniture " + std::to_string(id) + " does not exist in map '" + map + "'", "furniture");
    }
    const auto fr = storage::FindFurnitureInstance(c, map, id, true);
    FurnitureInstanceView v = ViewOf(*r, fr);
    if (fr) v.points = static_cast<std::int64_t>(DecodeCloudBlob(fr->cloud).size());
    return v;
  });
}

ExportedLayer FurnitureSegmentationService::Cloud(const std::string& map, std::int64_t id, engine::CloudFormat format) {
  const FurnitureInstanceView v = Get(map, id);
  if (!v.perceived) throw Error(ErrorCode::kUnprocessable, "furniture " + std::to_string(id) + " was entered by an operator and has no cloud", "furniture");
  const auto fr = store_.Read([&](storage::Connection& c) { return storage::FindFurnitureInstance(c, map, id, true); });
  const std::vector<Eigen::Vector3f> points = DecodeCloudBlob(fr ? fr->cloud : std::string());
  ExportedLayer out = CloudBytes(points, format);
  out.frame = CoordinateFrame::kMap;
  return out;
}

}  // namespace anchordb::services
