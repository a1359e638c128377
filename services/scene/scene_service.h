#pragma once
// Scene models anchored at camera poses (thesis 3.2-3.3) and their keyframes. Observing models live in memory (one
// mutex each) and are persisted as versioned blobs every `persist_every_frames` frames, on close and at shutdown; a
// model not in memory is loaded from the database on first use, so a restarted server continues an open model where
// its last persisted state stopped. Errors are anchordb::Error: kNotFound (map, scene, keyframe), kConflict (the
// model is not observing, or changed concurrently), kInvalidArgument / kUnprocessable (bad input, see the types).
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "engine/scene/merge_candidates.h"
#include "engine/scene/settle.h"
#include "engine/scene/supersession.h"
#include "schema/clock.h"
#include "services/common/exported_bytes.h"
#include "services/scene/keyframe_listener.h"
#include "services/scene/scene_types.h"
#include "storage/scene_repository.h"
#include "storage/store.h"

namespace anchordb::services {

struct SceneLimits : engine::SettleParams {  // settle_frames, settle_min_change_px, settle_tolerance_px (0 = off)
  int max_image_side = 4096;       // width and height of a model's camera
  int persist_every_frames = 30;   // frames between state checkpoints (1 = every frame is durable when answered)
};

// Which earlier models a new one merges (3.3.3: max_candidates, max_age_s, candidate_radius_m, min_overlap,
// frustum_far_m) and which it supersedes (3.3.4: supersede_distance_m, supersede_angle_rad).
struct MergeSettings : engine::MergeCandidateParams, engine::SupersessionParams {};

class SceneService {
 public:
  SceneService(storage::Store& store, SceneLimits limits, MergeSettings merge = {},
               const Clock& clock = SystemClock::Instance());
  ~SceneService();  // persists every model in memory

  // Opens a model at the request's camera pose and chooses the earlier models its first frame will merge.
  SceneInfo Open(const std::string& map, const OpenSceneRequest& request);
  // Applies a frame (the first one merges the chosen earlier models); stores the begin keyframe with the first frame
  // and a settled keyframe when a movement completed.
  FrameResult AddFrame(const std::string& map, std::int64_t id, const FrameInput& frame);
  SceneInfo Get(const std::string& map, std::int64_t id);
  // A layer as PNG (static: 16-bit mm; movable, dynamic: 8-bit mask; reliability: 8-bit weight, clamped at 255) or
  // raw (static: f32 metres; reliability: f32 weight; masks: u8), with X-Image-Width/-Height and X-Scene-Frames
  // headers. `clean` (movable only) applies the noise cleaning of 3.5.1. kInvalidArgument: clean with another layer.
  ExportedLayer Layer(const std::string& map, std::int64_t id, SceneLayerKind layer, SceneLayerEncoding encoding,
                      bool clean);
  SceneLayerSummary LayerSummary(const std::string& map, std::int64_t id, SceneLayerKind layer, bool clean);
  // Stores a manual keyframe of the latest frame (kConflict when none arrived since the model was loaded).
  KeyframeResult Keyframe(const std::string& map, std::int64_t id);
  // Ends the observation: an end keyframe, the state persisted, status closed.
  CloseResult Close(const std::string& map, std::int64_t id);
  std::vector<SceneInfo> List(const std::string& map, const SceneListFilter& filter);
  KeyframeInfo GetKeyframe(const std::string& map, std::int64_t id);
  // A keyframe's raw depth or static background as 16-bit PNG [mm].
  ExportedLayer KeyframeImage(const std::string& map, std::int64_t id, KeyframeImageKind which);

  // Receives every stored keyframe (the event layer); not owned, may be null.
  void SetKeyframeListener(KeyframeListener* listener) { listener_ = listener; }

  // Writes every in-memory model whose state changed since its last checkpoint.
  void PersistAll();

  const SceneLimits& limits() const { return limits_; }

 private:
  struct Model;
  struct PriorSnapshot;
  std::shared_ptr<Model> Acquire(const std::string& map, std::int64_t id);
  std::shared_ptr<Model> Load(const std::string& map, std::int64_t id);
  void Persist(Model& model);
  StoredKeyframe StoreKeyframe(Model& model, KeyframeKind kind, std::int64_t stamp_ns);
  storage::KeyframeRecord KeyframeRecordOf(const Model& model, KeyframeKind kind, std::int64_t stamp_ns,
                                           const std::vector<std::uint16_t>& background_mm) const;
  // After the keyframe `k` was committed as `id`: the model's keyframe bookkeeping and the listener's analysis.
  StoredKeyframe KeyframeStored(Model& model, const storage::KeyframeRecord& k, std::int64_t id, KeyframeKind kind,
                                std::int64_t stamp_ns, const std::vector<std::uint16_t>& background_mm);
  FrameResult ApplyAndStoreFrame(Model& model, std::int64_t id, const std::vector<std::uint16_t>& depth, double scale,
                                 const std::vector<std::uint8_t>& dynamic, std::int64_t stamp_ns);
  std::optional<KeyframeAnalysis> Analyse(const Model& model, const StoredKeyframe& keyframe, std::int64_t stamp_ns,
                                          const std::vector<std::uint16_t>& background_mm);
  SceneInfo Describe(const Model& model) const;
  std::vector<engine::MergeCandidate> SelectCandidates(const std::string& map, const OpenSceneRequest& request,
                                                       std::int64_t stamp_ns);
  PriorSnapshot ReadPriors(const Model& model);
  void MergeFirstFrame(Model& model, const std::vector<std::uint16_t>& depth, double scale,
                       const std::vector<std::uint8_t>& dynamic);

  storage::Store& store_;
  SceneLimits limits_;
  MergeSettings merge_;
  const Clock& clock_;
  KeyframeListener* listener_ = nullptr;
  std::mutex models_mutex_;
  std::map<std::int64_t, std::shared_ptr<Model>> models_;
};

}  // namespace anchordb::services
