#pragma once
// Scene models anchored at camera poses (thesis 3.2-3.3) and their keyframes. Observing models live in memory (one
// mutex each) and are checkpointed as versioned blobs every `persist_every_frames` frames, on close and at shutdown.
// With the frame journal on (the default), every frame is committed to the journal (storage/frame_journal.h) in one
// write transaction with its keyframe and checkpoint, if any, before it is answered, so every acknowledged frame is
// durable. A model not in memory is loaded on first use (after a restart: before its next frame is accepted) from its
// last checkpoint plus its journal, replayed without side effects (no keyframe or event is made twice; the settle
// detector continues from its journalled state), so a restarted server continues an open model exactly where the last
// acknowledged frame left it: the same layers, keyframes and detector state as an uninterrupted run. Errors are anchordb::Error: kNotFound (map, scene, keyframe), kConflict (the
// model is not observing, or changed concurrently), kInvalidArgument / kUnprocessable (bad input, see the types).
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "engine/cloud/cloud_io.h"
#include "engine/scene/merge_candidates.h"
#include "engine/scene/settle.h"
#include "engine/scene/supersession.h"
#include "schema/clock.h"
#include "services/common/exported_bytes.h"
#include "services/scene/keyframe_listener.h"
#include "services/scene/scene_types.h"
#include "storage/frame_journal.h"
#include "storage/store.h"

namespace anchordb::storage {
struct SceneRecord;
}  // namespace anchordb::storage

namespace anchordb::services {

struct SceneLimits : engine::SettleParams {  // settle_frames, settle_min_change_px, settle_tolerance_px (0 = off)
  int max_image_side = 4096;       // width and height of a model's camera
  int persist_every_frames = 30;   // frames between state checkpoints (bounds the journal replayed at a load)
  // Journal every frame before answering it (SPEC §8). Off: only checkpoints are durable (frames since the last one
  // are lost by a crash); the bench measures ingest both ways.
  bool frame_journal = true;
};

// Which earlier models a new one merges (3.3.3: max_candidates, max_age_s, candidate_radius_m, min_overlap,
// frustum_far_m) and which it supersedes (3.3.4: supersede_distance_m, supersede_angle_rad).
struct MergeSettings : engine::MergeCandidateParams, engine::SupersessionParams {
  // The localisation uncertainty of a scene model's pose when the client gives none (AMCL-class: 2-5 cm, 1-3 deg).
  double pose_sigma_translation_m = 0.03;
  double pose_sigma_rotation_rad = 0.035;
};

class SceneService {
 public:
  SceneService(storage::Store& store, SceneLimits limits, MergeSettings merge = {},
               const Clock& clock = SystemClock::Instance());
  ~SceneService();  // persists every model in memory

  // Opens a model at the request's camera pose and chooses the earlier models its first frame will merge.
  SceneInfo Open(const std::string& map, const OpenSceneRequest& request);
  // Applies a frame (the first one merges the chosen earlier models); stores the begin keyframe with the first frame
  // and a settled keyframe when a movement completed. A stored keyframe's change analysis is queued in the frame's
  // transaction and runs later (its `analysis` is pending), unless frame.wait_for_analysis: then the answer waits
  // for it, at most the listener's bound, with no lock held.
  FrameResult AddFrame(const std::string& map, std::int64_t id, const FrameInput& frame);
  SceneInfo Get(const std::string& map, std::int64_t id);
  // A layer as PNG (static: 16-bit mm; movable, dynamic: 8-bit mask; reliability: 8-bit weight, clamped at 255) or
  // raw (static: f32 metres; reliability: f32 weight; masks: u8), with the image's size and the frames seen.
  // `clean` (movable only) applies the noise cleaning of 3.5.1. kInvalidArgument: clean with another layer.
  ExportedLayer Layer(const std::string& map, std::int64_t id, SceneLayerKind layer, SceneLayerEncoding encoding,
                      bool clean);
  // The static layer (background) or the movable layer (its pixels at the depth of the latest frame: in memory, else
  // the model's newest keyframe) back-projected with the model's camera, in the map frame (merge-corrected pose, else
  // the opening pose) or the camera's optical frame, as PCD / PLY of x, y, z [m] (scene_clouds.cc), with the
  // point count, the frame and the frames seen. kInvalidArgument (field "layer") for another layer; kNotFound.
  ExportedLayer LayerCloud(const std::string& map, std::int64_t id, SceneLayerKind layer, bool map_frame,
                           engine::CloudFormat format);
  SceneLayerSummary LayerSummary(const std::string& map, std::int64_t id, SceneLayerKind layer, bool clean);
  // Stores a manual keyframe of the latest frame (kConflict when none arrived since the model was loaded); its
  // analysis as for AddFrame.
  KeyframeResult Keyframe(const std::string& map, std::int64_t id, bool wait_for_analysis = false);
  // Ends the observation: an end keyframe (its analysis as for AddFrame), the state persisted, status closed.
  CloseResult Close(const std::string& map, std::int64_t id, bool wait_for_analysis = false);
  std::vector<SceneInfo> List(const std::string& map, const SceneListFilter& filter);
  KeyframeInfo GetKeyframe(const std::string& map, std::int64_t id);
  // A keyframe's raw depth or static background as 16-bit PNG [mm].
  ExportedLayer KeyframeImage(const std::string& map, std::int64_t id, KeyframeImageKind which);

  // Queues the analysis of every stored keyframe (the event layer's queue); not owned, may be null.
  void SetKeyframeListener(KeyframeListener* listener) { listener_ = listener; }

  // Writes every in-memory model whose state changed since its last checkpoint.
  void PersistAll();

  const SceneLimits& limits() const { return limits_; }

 private:
  struct Model;
  struct PriorSnapshot;
  struct FrameStep;
  using LockedModel = std::pair<std::shared_ptr<Model>, std::unique_lock<std::mutex>>;
  std::shared_ptr<Model> Acquire(const std::string& map, std::int64_t id);
  // The model, locked and current: a copy evicted after a failed frame write is reloaded from the database.
  LockedModel Lock(const std::string& map, std::int64_t id);
  void Evict(Model& model);
  std::shared_ptr<Model> Load(const std::string& map, std::int64_t id);
  void Persist(Model& model);
  // Stores a keyframe of the latest frame and queues its analysis; `also` runs in the same write transaction,
  // `committed` after it.
  StoredKeyframe StoreKeyframe(Model& model, KeyframeKind kind, std::int64_t stamp_ns,
                               const std::function<void(storage::Connection&)>& also = {},
                               const std::function<void()>& committed = {});
  StoredKeyframe KeyframeStored(Model& model, std::int64_t keyframe_id, KeyframeKind kind);
  // Queues the analysis of a keyframe inserted in this transaction (nothing without a listener).
  void EnqueueAnalysis(storage::Connection& c, const Model& model, std::int64_t keyframe_id);
  // Waits (no lock held) for the analysis of the keyframe a request stored, bounded by the listener's setting.
  void AwaitAnalysis(std::optional<StoredKeyframe>& keyframe);
  FrameResult AddFrameLocked(const std::string& map, std::int64_t id, const FrameInput& frame);
  CloseResult CloseLocked(const std::string& map, std::int64_t id);
  SceneInfo Describe(const Model& model) const;
  std::vector<engine::MergeCandidate> SelectCandidates(const std::string& map, const OpenSceneRequest& request,
                                                       std::int64_t stamp_ns);
  PriorSnapshot ReadPriors(const Model& model);
  // A frame's effects, computed before anything is written (scene_journal.cc), its one write, and the model's
  // bookkeeping once that committed.
  FrameStep Step(const Model& model, const engine::SceneModelState& state, const engine::FrameCounts& counts,
                 const std::vector<std::uint16_t>& depth, double scale, std::int64_t stamp_ns,
                 std::optional<storage::JournalFrame> journal, const storage::SceneRecord* merged) const;
  bool WriteFrame(const Model& model, FrameStep& step, const std::function<bool(storage::Connection&)>& precondition);
  FrameResult FrameCommitted(Model& model, FrameStep& step);
  // The first frame of a model that merges earlier ones (scene_merge.cc).
  FrameResult AddMergingFrame(Model& model, const std::vector<std::uint16_t>& depth, double scale,
                              const std::vector<std::uint8_t>& dynamic, std::int64_t stamp_ns,
                              const std::optional<storage::JournalFrame>& journal);
  // Rebuilds a loaded model's state from its journal rows (scene_journal.cc).
  void Replay(Model& model, const std::vector<storage::JournalFrame>& rows) const;

  storage::Store& store_;
  SceneLimits limits_;
  MergeSettings merge_;
  const Clock& clock_;
  KeyframeListener* listener_ = nullptr;
  std::mutex models_mutex_;
  std::map<std::int64_t, std::shared_ptr<Model>> models_;
};

}  // namespace anchordb::services
