#pragma once
// Scene models anchored at camera poses (thesis 3.2-3.3) and their keyframes, behind the /scenes and /keyframes
// routes. Observing models live in memory (one mutex each) and are persisted as versioned blobs every
// `persist_every_frames` frames, on close and at shutdown; a model not in memory is loaded from the database on
// first use, so a restarted server continues an open model where its last persisted state stopped.
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "services/common/exported_bytes.h"
#include "services/scene/keyframe_listener.h"
#include "engine/scene/scene_model.h"
#include "storage/repositories.h"
#include "storage/scene_repository.h"
#include "storage/store.h"
#include "services/common/transitional_json.h"

namespace anchordb::services {

struct SceneLimits {
  int max_image_side = 4096;       // width and height of a model's camera
  int persist_every_frames = 30;   // frames between state checkpoints (1 = every frame is durable when answered)
  // A completed movement (3.3.4): after the movable layer changed by at least `settle_min_change_px` pixels (or as
  // many background pixels were reset farther: a removal), it stayed within `settle_tolerance_px` for
  // `settle_frames` frames without dynamic pixels -> a 'settled' keyframe that starts a new action layer. 0 = off.
  int settle_frames = 8;
  int settle_min_change_px = 400;
  int settle_tolerance_px = 60;
};

// Which earlier models a new one merges (3.3.3) and which it supersedes (3.3.4).
struct MergeSettings {
  int max_candidates = 5;                 // newest first
  double max_age_s = 30.0 * 24 * 3600;    // older models are not merged
  double candidate_radius_m = 6.0;        // camera positions farther apart are not considered
  double min_overlap = 0.05;              // fraction of the earlier background inside the new view frustum
  double frustum_far_m = 5.0;             // rear boundary of a view frustum (sensor range)
  double supersede_distance_m = 0.15;     // a new model this close ...
  double supersede_angle_rad = 0.1745;    // ... looking this similarly supersedes the older one
};

struct FrameInput {
  std::string_view body;           // the request body, or the `depth` part of a multipart body
  bool png = true;                 // PNG, else raw little-endian uint16
  std::optional<std::string_view> dynamic_png;  // 8-bit mask
  std::optional<std::int64_t> stamp_ns;
  std::optional<double> depth_scale;            // units per metre, overrides the model's
};

class SceneService {
 public:
  SceneService(storage::Store& store, SceneLimits limits, MergeSettings merge = {});
  ~SceneService();  // persists every model in memory

  Json Open(const std::string& map, const Json& body);
  Json AddFrame(const std::string& map, std::int64_t id, const FrameInput& frame);
  Json Get(const std::string& map, std::int64_t id);
  // layer: static | movable | dynamic | reliability; format: json | png | raw
  ExportedLayer Layer(const std::string& map, std::int64_t id, const std::string& layer, const std::string& format,
                      bool clean);
  Json Keyframe(const std::string& map, std::int64_t id);
  Json Close(const std::string& map, std::int64_t id);
  Json List(const std::string& map, const storage::SceneFilter& filter);
  Json GetKeyframe(const std::string& map, std::int64_t id);
  // which: depth | background (16-bit PNG, mm)
  ExportedLayer KeyframeImage(const std::string& map, std::int64_t id, const std::string& which);

  // Receives every stored keyframe (the event layer); not owned, may be null.
  void SetKeyframeListener(KeyframeListener* listener) { listener_ = listener; }

  // Writes every in-memory model whose state changed since its last checkpoint.
  void PersistAll();

 private:
  struct Model;
  std::shared_ptr<Model> Acquire(const std::string& map, std::int64_t id);
  void Persist(Model& model);
  // Stores a keyframe and lets the listener analyse it: {"keyframe": id, "action_layer", "analysis"}.
  Json StoreKeyframe(Model& model, const std::string& kind, std::int64_t stamp_ns);
  Json Describe(const Model& model) const;
  Json SelectCandidates(const std::string& map, const PinholeIntrinsics& K, const Pose3& pose, std::int64_t stamp_ns);
  void MergeFirstFrame(Model& model, const std::vector<std::uint16_t>& depth, double scale,
                       const std::vector<std::uint8_t>& dynamic);

  storage::Store& store_;
  SceneLimits limits_;
  MergeSettings merge_;
  KeyframeListener* listener_ = nullptr;
  std::mutex models_mutex_;
  std::map<std::int64_t, std::shared_ptr<Model>> models_;
};

}  // namespace anchordb::services
