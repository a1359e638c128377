#include "services/scene/scene_service.h"

#include "engine/scene/depth_image.h"
#include "engine/scene/projection.h"
#include "services/scene/scene_pose_covariance.h"
#include "services/scene/scene_service_internal.h"

namespace anchordb::services {

using namespace scene_detail;

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
  const engine::Matrix6d pose_covariance = scene_pose::Resolve(request, merge_);
  const PinholeIntrinsics& K = request.camera;
  const Pose3& pose = request.X_MapCamera;
  const std::int64_t stamp = request.stamp_ns.value_or(clock_.NowNs());
  auto model = std::make_shared<Model>();
  model->K = K;
  model->params = request.params;
  model->state = engine::NewSceneModel(K.width, K.height);
  storage::SceneRecord& r = model->record;
  r.map_id = map;
  r.camera = K;
  r.pose = pose;
  r.pose_covariance = scene_pose::RowMajor(pose_covariance);
  r.beta = request.params.model.beta;
  r.dynamic_mode = NameOf(kDynamicModeNames, request.params.model.dynamic_mode);
  r.depth_scale = request.params.depth_scale;
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

SceneService::LockedModel SceneService::Lock(const std::string& map, std::int64_t id) {
  for (;;) {
    auto model = Acquire(map, id);
    std::unique_lock<std::mutex> lock(model->mutex);
    if (!model->evicted) return {std::move(model), std::move(lock)};
  }
}

void SceneService::Evict(Model& m) {
  m.evicted = true;
  std::lock_guard<std::mutex> lock(models_mutex_);
  auto it = models_.find(m.record.id);
  if (it != models_.end() && it->second.get() == &m) models_.erase(it);
}

std::shared_ptr<SceneService::Model> SceneService::Load(const std::string& map, std::int64_t id) {
  auto model = std::make_shared<Model>();
  std::vector<storage::JournalFrame> journal;
  auto record = store_.Read([&](storage::Connection& c) {  // one snapshot: checkpoint, keyframes and journal agree
    RequireMap(c, map);
    auto found = storage::FindScene(c, map, id, true);
    if (found) {
      for (const auto& k : storage::ListKeyframes(c, map, id)) {
        model->has_begin_keyframe = model->has_begin_keyframe || k.kind == "begin";
        model->next_action_layer = std::max(model->next_action_layer, k.action_layer + 1);
      }
      journal = storage::ReadJournal(c, id, found->frames);
    }
    return found;
  });
  if (!record) throw Error(ErrorCode::kNotFound, "scene " + std::to_string(id) + " does not exist in map '" + map + "'", "scene");
  model->K = record->camera;
  model->params = StoredParams(*record);
  model->merge = scene_stored::DecodeMergeReport(record->merge_report, record->id);
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
  Replay(*model, journal);
  return model;
}

void SceneService::Persist(Model& m) {
  const storage::SceneRecord r = StateRecord(m.record, m.K, m.state);  // encoded before the write
  store_.Write([&](storage::Connection& c) { WriteCheckpoint(c, r, m.record.state_version); });
  m.Persisted(r);
}

StoredKeyframe SceneService::StoreKeyframe(Model& m, KeyframeKind kind, std::int64_t stamp_ns,
                                           const std::function<void(storage::Connection&)>& also,
                                           const std::function<void()>& committed) {
  if (m.last_depth_mm.empty()) {
    throw Error(ErrorCode::kConflict, "scene " + std::to_string(m.record.id) + " has received no frame since it was (re)loaded");
  }
  const std::vector<std::uint16_t> background_mm = ToMillimetres(m.state.background_m);
  const storage::KeyframeRecord k = KeyframeRecordOf(m.record, m.K, m.next_action_layer, kind, stamp_ns, m.last_depth_mm, background_mm);
  engine::SettleDetector settle = m.settle;
  settle.OnKeyframe(m.last_counts.movable);
  const storage::JournalModelAfter after = scene_stored::EncodeModelAfter(m.last_counts, settle.state());
  const std::int64_t id = store_.Write([&](storage::Connection& c) {
    const std::int64_t inserted = storage::InsertKeyframe(c, k);
    EnqueueAnalysis(c, m, inserted);
    // The detector after this keyframe survives a crash with the latest frame's row (none when it is not journalled).
    storage::UpdateJournalModelAfter(c, m.record.id, m.state.frames, after);
    if (also) also(c);
    return inserted;
  });
  m.settle = settle;
  if (committed) committed();
  return KeyframeStored(m, id, kind);
}

void SceneService::EnqueueAnalysis(storage::Connection& c, const Model& m, std::int64_t keyframe_id) {
  if (listener_) listener_->Enqueue(c, {m.record.map_id, m.record.id, keyframe_id, clock_.NowNs()});
}

// The keyframe and its queued analysis committed: the analysis may start; the answer does not wait for it.
StoredKeyframe SceneService::KeyframeStored(Model& m, std::int64_t keyframe_id, KeyframeKind kind) {
  StoredKeyframe out;
  out.id = keyframe_id;
  out.kind = kind;
  out.action_layer = m.next_action_layer;
  ++m.next_action_layer;
  if (listener_) {
    listener_->Enqueued(m.record.map_id);
    out.analysis = KeyframeAnalysisStatus{AnalysisState::kPending, keyframe_id, std::nullopt, 0, std::nullopt};
  }
  return out;
}

// Called with no model lock held: the analysis never waits for the model, and nothing the model's readers need waits
// for the analysis.
void SceneService::AwaitAnalysis(std::optional<StoredKeyframe>& k) {
  if (k && k->analysis && listener_) k->analysis = listener_->Await(k->id);
}

FrameResult SceneService::AddFrame(const std::string& map, std::int64_t id, const FrameInput& in) {
  FrameResult out = AddFrameLocked(map, id, in);
  if (in.wait_for_analysis) AwaitAnalysis(out.keyframe);
  return out;
}

FrameResult SceneService::AddFrameLocked(const std::string& map, std::int64_t id, const FrameInput& in) {
  auto [model, lock] = Lock(map, id);
  Model& m = *model;
  RequireObserving(m.record, "", "; open a new one");
  if (listener_) listener_->Admit(map);  // a map whose analyses are far behind takes no frame (nothing changed yet)
  auto [depth, dynamic] = DecodeFrame(in, m.K);  // nothing is journalled or changed before the frame is valid
  const double scale = in.depth_scale ? CheckDepthScale(*in.depth_scale, "depth_scale") : m.params.depth_scale;
  const std::int64_t stamp = in.stamp_ns.value_or(clock_.NowNs());
  std::optional<storage::JournalFrame> journal;
  if (limits_.frame_journal) journal = JournalRowOf(m.record.id, m.K, in, depth.pixels, scale, stamp);
  if (m.merge.pending.value_or(false)) return AddMergingFrame(m, depth.pixels, scale, dynamic, stamp, journal);
  try {
    const engine::FrameCounts counts = engine::ApplyFrame(m.state, depth.pixels, scale, dynamic, m.params.model);
    FrameStep step = Step(m, m.state, counts, depth.pixels, scale, stamp, std::move(journal), nullptr);
    WriteFrame(m, step, {});
    return FrameCommitted(m, step);
  } catch (...) {
    // The state may hold a frame the database does not: with the journal, the next request reloads the model (its
    // checkpoint plus its journal) instead of answering from it. Without it, the frame stays in memory, as before.
    if (limits_.frame_journal) Evict(m);
    throw;
  }
}

KeyframeResult SceneService::Keyframe(const std::string& map, std::int64_t id, bool wait_for_analysis) {
  std::optional<StoredKeyframe> stored;
  {
    auto [model, lock] = Lock(map, id);
    RequireObserving(model->record);
    if (listener_) listener_->Admit(map);
    const std::int64_t stamp = model->record.last_frame_ns.value_or(clock_.NowNs());
    stored = StoreKeyframe(*model, KeyframeKind::kManual, stamp);
  }
  if (wait_for_analysis) AwaitAnalysis(stored);
  return {id, std::move(*stored)};
}

CloseResult SceneService::Close(const std::string& map, std::int64_t id, bool wait_for_analysis) {
  CloseResult out = CloseLocked(map, id);
  if (wait_for_analysis) AwaitAnalysis(out.keyframe);
  return out;
}

CloseResult SceneService::CloseLocked(const std::string& map, std::int64_t id) {
  auto [model, lock] = Lock(map, id);
  Model& m = *model;
  RequireObserving(m.record, "already ");
  CloseResult out;
  out.scene_id = id;
  const std::int64_t end = m.record.last_frame_ns.value_or(clock_.NowNs());
  // The end keyframe, the final checkpoint (the journal goes with it) and the status in one transaction.
  const storage::SceneRecord checkpoint = StateRecord(m.record, m.K, m.state);
  const auto finish = [&](storage::Connection& c) {
    storage::UpdateSceneState(c, checkpoint, m.record.state_version);
    storage::DeleteJournal(c, id);
    storage::UpdateSceneStatus(c, id, "closed", end, std::nullopt);
  };
  const auto closed = [&] {
    m.Persisted(checkpoint);
    m.record.status = "closed";
    m.record.ended_ns = end;
    std::lock_guard<std::mutex> models_lock(models_mutex_);  // closed models are not kept in memory
    models_.erase(id);
  };
  if (!m.last_depth_mm.empty()) {
    out.keyframe = StoreKeyframe(m, KeyframeKind::kEnd, end, finish, closed);  // its analysis queued with the close
  } else {
    store_.Write(finish);
    closed();
  }
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
