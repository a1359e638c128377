#pragma once
// Internal to services/scene/*.cc: the in-memory state of a scene model and the helpers its files share.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <mutex>

#include "engine/scene/scene_model.h"
#include "schema/error.h"
#include "services/scene/scene_stored_documents.h"
#include "services/scene/scene_service.h"
#include "storage/blob_codec.h"
#include "storage/frame_journal.h"
#include "storage/scene_repository.h"
#include "services/common/require.h"

namespace anchordb::services {

using storage::BlobElement;

namespace scene_detail {

inline double CheckDepthScale(double v, const std::string& field) {
  if (!(v > 0.0) || v > 1e6) throw Error(ErrorCode::kUnprocessable, "depth_scale must be in (0, 1e6] units per metre", field);
  return v;
}

inline std::string EncodeF32(const std::vector<float>& v, int w, int h) {
  return storage::EncodeBlob(BlobElement::kF32, {static_cast<std::uint32_t>(h), static_cast<std::uint32_t>(w)},
                             storage::AsBytes(v), 1);
}

template <typename T>
std::vector<T> DecodeAs(const std::string& blob, BlobElement element, std::size_t count) {
  auto out = storage::DecodeArray<T>(blob, element, count);
  if (!out) throw Error(ErrorCode::kInternal, "stored scene state does not match the model's camera");
  return std::move(*out);
}

// A frame's depth in `scale` sensor units per metre as millimetres (what keyframes store).
inline std::vector<std::uint16_t> DepthMillimetres(const std::vector<std::uint16_t>& depth, double scale) {
  std::vector<std::uint16_t> mm(depth.size());
  for (std::size_t i = 0; i < depth.size(); ++i) {
    mm[i] = static_cast<std::uint16_t>(std::min(65535.0, std::round(depth[i] * 1000.0 / scale)));
  }
  return mm;
}

inline std::vector<std::uint16_t> ToMillimetres(const std::vector<float>& metres) {
  std::vector<std::uint16_t> mm(metres.size());
  for (std::size_t i = 0; i < metres.size(); ++i) {
    mm[i] = static_cast<std::uint16_t>(std::clamp(std::lround(metres[i] * 1000.0f), 0L, 65535L));
  }
  return mm;
}

// A stored model's parameters (its dynamic mode by its one name table).
inline SceneParams StoredParams(const storage::SceneRecord& r) {
  SceneParams params;
  params.model.beta = r.beta;
  params.model.dynamic_mode = ValueOf(kDynamicModeNames, r.dynamic_mode).value_or(engine::DynamicMode::kExcludeFromInput);
  params.depth_scale = r.depth_scale;
  return params;
}

using services::RequireMap;

// A copy of `base` carrying the encoded state (blobs, frames, next state_version), for UpdateSceneState.
inline storage::SceneRecord StateRecord(const storage::SceneRecord& base, const PinholeIntrinsics& K,
                                        const engine::SceneModelState& state) {
  storage::SceneRecord r = base;
  r.background = EncodeF32(state.background_m, K.width, K.height);
  r.weight = EncodeF32(state.weight, K.width, K.height);
  std::vector<std::uint8_t> labels(state.movable);
  labels.insert(labels.end(), state.dynamic.begin(), state.dynamic.end());
  r.labels = storage::EncodeBlob(BlobElement::kU8, {2, static_cast<std::uint32_t>(K.height), static_cast<std::uint32_t>(K.width)},
                                 storage::AsBytes(labels), 1);
  r.frames = state.frames;
  r.state_version = base.state_version + 1;
  return r;
}

// A checkpoint (`r`, a StateRecord) and the trim of the journal rows it covers, in the caller's transaction.
inline void WriteCheckpoint(storage::Connection& c, const storage::SceneRecord& r, std::int64_t expected_state_version) {
  storage::UpdateSceneState(c, r, expected_state_version);
  storage::TrimJournal(c, r.id, r.frames);
}

}  // namespace scene_detail

struct SceneService::Model {
  std::mutex mutex;
  storage::SceneRecord record;  // state blobs not kept here; merge_report follows `merge`
  PinholeIntrinsics K;
  SceneParams params;
  MergeReport merge;
  engine::SceneModelState state;
  int unpersisted_frames = 0;                // frames since the last checkpoint
  std::int64_t journalled_frames = 0;        // frames up to which the journal holds every frame (0: none)
  bool evicted = false;                      // a failed frame write left this copy ahead of the database
  std::vector<std::uint16_t> last_depth_mm;  // the latest frame, for keyframes
  bool has_begin_keyframe = false;
  engine::FrameCounts last_counts;
  std::int64_t next_action_layer = 0;  // the layer the next keyframe opens
  engine::SettleDetector settle;       // SceneLimits::settle_*

  void SetMergeReport(MergeReport report) {
    merge = std::move(report);
    record.merge_report = scene_stored::EncodeMergeReport(merge);
  }
  // `written` (a StateRecord of this model) was committed.
  void Persisted(const storage::SceneRecord& written) {
    record.state_version = written.state_version;
    record.frames = written.frames;
    unpersisted_frames = 0;
  }
  // Frames a crash would not lose.
  std::int64_t DurableFrames() const { return std::max(record.frames, journalled_frames); }
};

// What one frame changes, computed before anything is written (SceneService::Step).
struct SceneService::FrameStep {
  std::int64_t stamp_ns = 0;
  engine::FrameCounts counts;
  engine::SettleDetector settle;            // after the frame and its keyframe
  std::vector<std::uint16_t> depth_mm;      // the frame in millimetres: the model's next last_depth_mm
  std::optional<KeyframeKind> keyframe;     // the begin or a settled keyframe this frame stores
  storage::KeyframeRecord keyframe_record;  // when `keyframe`
  std::int64_t keyframe_id = 0;             // set by WriteFrame
  std::vector<std::uint16_t> background_mm; // when `keyframe`: what its record stores
  std::optional<storage::SceneRecord> checkpoint;
  std::optional<storage::JournalFrame> journal;
};

namespace scene_detail {  // scene_journal.cc

// A keyframe of `scene` (camera K) showing `depth_mm` over `background_mm`, opening `action_layer`.
storage::KeyframeRecord KeyframeRecordOf(const storage::SceneRecord& scene, const PinholeIntrinsics& K,
                                         std::int64_t action_layer, KeyframeKind kind, std::int64_t stamp_ns,
                                         const std::vector<std::uint16_t>& depth_mm,
                                         const std::vector<std::uint16_t>& background_mm);
// The journal row of a validated frame (without frame number and model_after: SceneService::Step sets them).
storage::JournalFrame JournalRowOf(std::int64_t scene_id, const PinholeIntrinsics& K, const FrameInput& in,
                                   const std::vector<std::uint16_t>& depth, double scale, std::int64_t stamp_ns);

}  // namespace scene_detail

}  // namespace anchordb::services
