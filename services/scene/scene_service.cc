#include "services/scene/scene_service.h"

#include "engine/scene/depth_image.h"
#include "engine/scene/projection.h"
#include "services/scene/scene_service_internal.h"

namespace anchordb::services {

using namespace scene_detail;
namespace docs = scene_documents;

namespace {

void CheckOpenRequest(const OpenSceneRequest& r, int max_side) {
  const PinholeIntrinsics& K = r.camera;
  if (K.width < 1 || K.height < 1 || K.width > max_side || K.height > max_side) {
    throw Error(ErrorCode::kUnprocessable, "camera width and height must be in [1, " + std::to_string(max_side) + "]", "camera.width");
  }
  if (K.fx <= 0 || K.fy <= 0) throw Error(ErrorCode::kUnprocessable, "camera fx and fy must be positive", "camera.fx");
  const double beta = r.params.model.beta;
  if (!(beta > 0.0 && beta <= 1.0)) throw Error(ErrorCode::kUnprocessable, "beta must be in (0, 1]", "params.beta");
  CheckDepthScale(r.params.depth_scale, "params.depth_scale");
}

std::string SizeMismatch(const std::string& what, int w, int h, const PinholeIntrinsics& K) {
  return what + " is " + std::to_string(w) + "x" + std::to_string(h) + " but the model's camera is " +
         std::to_string(K.width) + "x" + std::to_string(K.height);
}

// The frame's depth, checked against the camera (a PNG's declared size before decoding: a few bytes may declare a
// huge image), and its dynamic mask (empty when none).
std::pair<engine::DepthImage, std::vector<std::uint8_t>> DecodeFrame(const FrameInput& in, const PinholeIntrinsics& K) {
  const auto declared = in.png ? engine::PngSize(in.body) : std::nullopt;
  if (declared && (declared->first != K.width || declared->second != K.height)) {
    throw Error(ErrorCode::kUnprocessable, SizeMismatch("depth", declared->first, declared->second, K), "depth");
  }
  engine::DepthImage depth = in.png ? engine::DecodeDepthPng(in.body, "depth") : engine::DecodeDepthRaw(in.body, K.width, K.height, "depth");
  if (depth.width != K.width || depth.height != K.height) {
    throw Error(ErrorCode::kUnprocessable, SizeMismatch("depth", depth.width, depth.height, K), "depth");
  }
  std::vector<std::uint8_t> dynamic;
  if (in.dynamic_png) {
    engine::MaskImage mask = engine::DecodeMaskPng(*in.dynamic_png, "dynamic");
    if (mask.width != K.width || mask.height != K.height) {
      throw Error(ErrorCode::kUnprocessable, "the dynamic mask's size differs from the model's camera", "dynamic");
    }
    dynamic = std::move(mask.pixels);
  }
  return {std::move(depth), std::move(dynamic)};
}

void RequireObserving(const storage::SceneRecord& r, const std::string& before = "", const std::string& after = "") {
  if (r.status != "observing") {
    throw Error(ErrorCode::kConflict, "scene " + std::to_string(r.id) + " is " + before + r.status + after, "scene");
  }
}

}  // namespace

SceneService::SceneService(storage::Store& store, SceneLimits limits, MergeSettings merge, const Clock& clock)
    : store_(store), limits_(limits), merge_(merge), clock_(clock) {}

SceneService::~SceneService() {
  try {
    PersistAll();
  } catch (...) {
    // Shutdown must not throw; an unpersisted tail is lost exactly as on a crash.
  }
}

SceneInfo SceneService::Open(const std::string& map, const OpenSceneRequest& request) {
  CheckOpenRequest(request, limits_.max_image_side);
  const PinholeIntrinsics& K = request.camera;
  const Pose3& pose = request.X_MapCamera;
  const std::int64_t stamp = request.stamp_ns.value_or(clock_.NowNs());
  auto model = std::make_shared<Model>();
  model->K = K;
  model->params = request.params;
  model->state = engine::NewSceneModel(K.width, K.height);
  storage::SceneRecord& r = model->record;
  r.map_id = map;
  r.intrinsics_json = docs::CameraDocument(K).dump();
  r.pose_json = docs::PoseDocument(pose).dump();
  r.x_m = pose.position_m.x();
  r.y_m = pose.position_m.y();
  r.z_m = pose.position_m.z();
  r.params_json = docs::ParamsDocument(request.params).dump();
  MergeReport report;
  report.requested = request.merge;
  report.strategy = request.merge_strategy;
  if (request.merge) {
    report.candidates = SelectCandidates(map, request, stamp);
    report.pending = !report.candidates.empty();  // the merge runs with the first frame (ICP needs it)
  }
  model->SetMergeReport(std::move(report));
  r.started_ns = stamp;
  r.id = store_.Write([&](storage::Connection& c) {
    RequireMap(c, map);
    return storage::InsertScene(c, r);
  });
  {
    std::lock_guard<std::mutex> lock(models_mutex_);
    models_[r.id] = model;
  }
  std::lock_guard<std::mutex> lock(model->mutex);
  return Describe(*model);
}

std::shared_ptr<SceneService::Model> SceneService::Acquire(const std::string& map, std::int64_t id) {
  {
    std::lock_guard<std::mutex> lock(models_mutex_);
    auto it = models_.find(id);
    if (it != models_.end()) {
      if (it->second->record.map_id != map) throw Error(ErrorCode::kNotFound, "scene " + std::to_string(id) + " is not in map '" + map + "'", "scene");
      return it->second;
    }
  }
  auto model = Load(map, id);
  if (model->record.status != "observing") return model;  // finished models are read from the database each time
  std::lock_guard<std::mutex> lock(models_mutex_);
  auto [it, inserted] = models_.emplace(id, model);
  return it->second;  // another thread may have loaded it first: use that one
}

std::shared_ptr<SceneService::Model> SceneService::Load(const std::string& map, std::int64_t id) {
  auto model = std::make_shared<Model>();
  auto record = store_.Read([&](storage::Connection& c) {
    RequireMap(c, map);
    auto found = storage::FindScene(c, map, id, true);
    if (found) {
      for (const auto& k : storage::ListKeyframes(c, map, id)) {
        model->has_begin_keyframe = model->has_begin_keyframe || k.kind == "begin";
        model->next_action_layer = std::max(model->next_action_layer, k.action_layer + 1);
      }
    }
    return found;
  });
  if (!record) throw Error(ErrorCode::kNotFound, "scene " + std::to_string(id) + " does not exist in map '" + map + "'", "scene");
  model->K = docs::CameraFromDocument(json::Json::parse(record->intrinsics_json));
  model->params = docs::ParamsFromDocument(json::Json::parse(record->params_json));
  model->merge = docs::MergeReportFromDocument(json::Json::parse(record->merge_report_json));  // the stored text is kept
  model->state = engine::NewSceneModel(model->K.width, model->K.height);
  const std::size_t n = static_cast<std::size_t>(model->K.width) * model->K.height;
  if (record->state_version > 0) {
    model->state.background_m = DecodeAs<float>(record->background, BlobElement::kF32, n);
    model->state.weight = DecodeAs<float>(record->weight, BlobElement::kF32, n);
    const auto labels = DecodeAs<std::uint8_t>(record->labels, BlobElement::kU8, 2 * n);
    model->state.movable.assign(labels.begin(), labels.begin() + n);
    model->state.dynamic.assign(labels.begin() + n, labels.end());
    model->state.frames = record->frames;
  }
  record->background.clear();
  record->weight.clear();
  record->labels.clear();
  model->record = std::move(*record);
  return model;
}

void SceneService::Persist(Model& m) {
  const storage::SceneRecord r = StateRecord(m.record, m.K, m.state);  // encoded before the write
  store_.Write([&](storage::Connection& c) { storage::UpdateSceneState(c, r, m.record.state_version); });
  m.Persisted(r);
}

StoredKeyframe SceneService::StoreKeyframe(Model& m, KeyframeKind kind, std::int64_t stamp_ns) {
  const std::vector<std::uint16_t> background_mm = ToMillimetres(m.state.background_m);
  const storage::KeyframeRecord k = KeyframeRecordOf(m, kind, stamp_ns, background_mm);
  const std::int64_t id = store_.Write([&](storage::Connection& c) { return storage::InsertKeyframe(c, k); });
  return KeyframeStored(m, k, id, kind, stamp_ns, background_mm);
}

storage::KeyframeRecord SceneService::KeyframeRecordOf(const Model& m, KeyframeKind kind, std::int64_t stamp_ns,
                                                       const std::vector<std::uint16_t>& background_mm) const {
  if (m.last_depth_mm.empty()) {
    throw Error(ErrorCode::kConflict, "scene " + std::to_string(m.record.id) + " has received no frame since it was (re)loaded");
  }
  storage::KeyframeRecord k;
  k.map_id = m.record.map_id;
  k.scene_id = m.record.id;
  k.kind = NameOf(kKeyframeKindNames, kind);
  k.stamp_ns = stamp_ns;
  k.width = m.K.width;
  k.height = m.K.height;
  k.action_layer = m.next_action_layer;
  const std::vector<std::uint32_t> shape = {static_cast<std::uint32_t>(m.K.height), static_cast<std::uint32_t>(m.K.width)};
  k.depth = storage::EncodeBlob(BlobElement::kU16, shape, storage::AsBytes(m.last_depth_mm), 3, storage::BlobFilter::kDeltaShuffle16);
  k.background = storage::EncodeBlob(BlobElement::kU16, shape, storage::AsBytes(background_mm), 3, storage::BlobFilter::kDeltaShuffle16);
  k.raw_bytes = static_cast<std::int64_t>(2 * 2 * m.last_depth_mm.size());
  k.stored_bytes = static_cast<std::int64_t>(k.depth.size() + k.background.size());
  return k;
}

StoredKeyframe SceneService::KeyframeStored(Model& m, const storage::KeyframeRecord& k, std::int64_t id, KeyframeKind kind,
                                            std::int64_t stamp_ns, const std::vector<std::uint16_t>& background_mm) {
  StoredKeyframe out;
  out.id = id;
  out.kind = kind;
  out.action_layer = k.action_layer;
  ++m.next_action_layer;
  m.settle.OnKeyframe(m.last_counts.movable);
  try {
    out.analysis = Analyse(m, out, stamp_ns, background_mm);
  } catch (const Error& e) {
    // The keyframe is committed; its analysis could not be read or written now (the disk fails or is full, memory
    // ran out). The answer goes without an analysis rather than an error that would make the client send again
    // what is stored already. (Issue 12: the analysis belongs in the keyframe's transaction.)
    if (e.code() != ErrorCode::kUnavailable && e.code() != ErrorCode::kInsufficientStorage) throw;
  }
  return out;
}

// The one place the keyframe listener is called; its summary goes into the response as it is.
std::optional<KeyframeAnalysis> SceneService::Analyse(const Model& m, const StoredKeyframe& k, std::int64_t stamp_ns,
                                                      const std::vector<std::uint16_t>& background_mm) {
  if (!listener_) return std::nullopt;
  KeyframeNotice n;
  n.map = m.record.map_id;
  n.scene_id = m.record.id;
  n.keyframe_id = k.id;
  n.kind = NameOf(kKeyframeKindNames, k.kind);
  n.stamp_ns = stamp_ns;
  n.action_layer = k.action_layer;
  n.K = m.K;
  n.beta = m.params.model.beta;
  const auto& corrected = m.merge.X_MapCamera_corrected;
  n.X_MapCamera = engine::ToIsometry(corrected ? json::AsPose3(docs::PoseDocument(*corrected), "pose") : StoredPose(m.record.pose_json));
  for (const MergedModel& used : m.merge.models_used) n.merged_scenes.push_back(used.scene_id);
  n.depth_mm = &m.last_depth_mm;
  n.background_mm = &background_mm;
  return listener_->OnKeyframe(n);
}

FrameResult SceneService::AddFrame(const std::string& map, std::int64_t id, const FrameInput& in) {
  auto model = Acquire(map, id);
  std::lock_guard<std::mutex> lock(model->mutex);
  Model& m = *model;
  RequireObserving(m.record, "", "; open a new one");
  auto [depth, dynamic] = DecodeFrame(in, m.K);
  const double scale = in.depth_scale ? CheckDepthScale(*in.depth_scale, "depth_scale") : m.params.depth_scale;
  const std::int64_t stamp = in.stamp_ns.value_or(clock_.NowNs());
  // A frame answered with an error (a failed keyframe or checkpoint write) must leave the model as it was: the
  // in-memory model never claims a frame the client was not told was taken. When the failure came after a committed
  // state (the first frame's merge), the model is reloaded from the database instead.
  auto undo = std::make_tuple(m.state, m.last_counts, m.last_depth_mm, m.record.last_frame_ns, m.unpersisted_frames,
                              m.settle, m.has_begin_keyframe, m.next_action_layer);
  const std::int64_t state_version = m.record.state_version;
  try {
    return ApplyAndStoreFrame(m, id, depth.pixels, scale, dynamic, stamp);
  } catch (...) {
    if (m.record.state_version == state_version) {
      std::tie(m.state, m.last_counts, m.last_depth_mm, m.record.last_frame_ns, m.unpersisted_frames, m.settle,
               m.has_begin_keyframe, m.next_action_layer) = std::move(undo);
    } else {
      std::lock_guard<std::mutex> models_lock(models_mutex_);
      models_.erase(id);
    }
    throw;
  }
}

FrameResult SceneService::ApplyAndStoreFrame(Model& m, std::int64_t id, const std::vector<std::uint16_t>& depth, double scale,
                                             const std::vector<std::uint8_t>& dynamic, std::int64_t stamp) {
  if (m.merge.pending.value_or(false)) {
    MergeFirstFrame(m, depth, scale, dynamic);
  } else {
    m.last_counts = engine::ApplyFrame(m.state, depth, scale, dynamic, m.params.model);
  }
  m.last_depth_mm.resize(depth.size());
  for (std::size_t i = 0; i < depth.size(); ++i) {
    m.last_depth_mm[i] = static_cast<std::uint16_t>(std::min(65535.0, std::round(depth[i] * 1000.0 / scale)));
  }
  m.record.last_frame_ns = stamp;
  ++m.unpersisted_frames;
  FrameResult out;
  out.scene_id = id;
  out.frames = m.state.frames;
  const bool settled = m.settle.OnFrame(m.last_counts, limits_);  // a completed movement (3.3.4)
  if (!m.has_begin_keyframe) {
    out.keyframe = StoreKeyframe(m, KeyframeKind::kBegin, stamp);
    m.has_begin_keyframe = true;
  } else if (settled) {
    out.keyframe = StoreKeyframe(m, KeyframeKind::kSettled, stamp);
  }
  if (m.unpersisted_frames >= limits_.persist_every_frames) Persist(m);
  out.persisted_frames = m.record.frames;
  out.pixels = m.last_counts;
  return out;
}

KeyframeResult SceneService::Keyframe(const std::string& map, std::int64_t id) {
  auto model = Acquire(map, id);
  std::lock_guard<std::mutex> lock(model->mutex);
  RequireObserving(model->record);
  const std::int64_t stamp = model->record.last_frame_ns.value_or(clock_.NowNs());
  return {id, StoreKeyframe(*model, KeyframeKind::kManual, stamp)};
}

CloseResult SceneService::Close(const std::string& map, std::int64_t id) {
  auto model = Acquire(map, id);
  std::lock_guard<std::mutex> lock(model->mutex);
  Model& m = *model;
  RequireObserving(m.record, "already ");
  CloseResult out;
  out.scene_id = id;
  const std::int64_t end = m.record.last_frame_ns.value_or(clock_.NowNs());
  // The end keyframe, the state and the status in one transaction: a failure leaves the model observing and
  // nothing of the close written, so the close can be sent again.
  const std::vector<std::uint16_t> background_mm = ToMillimetres(m.state.background_m);
  std::optional<storage::KeyframeRecord> k;
  if (!m.last_depth_mm.empty()) k = KeyframeRecordOf(m, KeyframeKind::kEnd, end, background_mm);
  const storage::SceneRecord state = StateRecord(m.record, m.K, m.state);
  const std::int64_t keyframe_id = store_.Write([&](storage::Connection& c) {
    const std::int64_t kid = k ? storage::InsertKeyframe(c, *k) : 0;
    storage::UpdateSceneState(c, state, m.record.state_version);
    storage::UpdateSceneStatus(c, id, "closed", end, std::nullopt);
    return kid;
  });
  m.Persisted(state);
  m.record.status = "closed";
  m.record.ended_ns = end;
  {
    std::lock_guard<std::mutex> models_lock(models_mutex_);  // closed models are not kept in memory
    models_.erase(id);
  }
  if (k) out.keyframe = KeyframeStored(m, *k, keyframe_id, KeyframeKind::kEnd, end, background_mm);
  out.status = SceneStatus::kClosed;
  out.frames = m.state.frames;
  return out;
}

void SceneService::PersistAll() {
  std::vector<std::shared_ptr<Model>> models;
  {
    std::lock_guard<std::mutex> lock(models_mutex_);
    for (auto& [id, m] : models_) models.push_back(m);
  }
  for (auto& m : models) {
    std::lock_guard<std::mutex> lock(m->mutex);
    if (m->unpersisted_frames > 0) Persist(*m);
  }
}

}  // namespace anchordb::services
