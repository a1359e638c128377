// A stored keyframe as its (queued) change analysis sees it: the same values the frame request had in memory when it
// stored the keyframe. The images are the keyframe row's lossless blobs (the depth in mm the model kept of its latest
// frame, the background it rounded to mm), the camera and beta are the scene row's, and the pose is the merge-corrected
// one of the scene's merge report (written with the merging frame, before any later keyframe) or else the opening pose.
#include "engine/scene/projection.h"
#include "services/common/stored_pose.h"
#include "services/scene/keyframe_listener.h"
#include "services/scene/scene_service_internal.h"

namespace anchordb::services {

using namespace scene_detail;

std::optional<KeyframeNotice> LoadKeyframeNotice(storage::Connection& c, const std::string& map, std::int64_t keyframe_id) {
  const auto k = storage::FindKeyframe(c, map, keyframe_id, true);
  if (!k) return std::nullopt;
  const auto scene = storage::FindScene(c, map, k->scene_id, false);
  if (!scene) return std::nullopt;
  KeyframeNotice n;
  n.map = map;
  n.scene_id = k->scene_id;
  n.keyframe_id = k->id;
  n.kind = k->kind;
  n.stamp_ns = k->stamp_ns;
  n.action_layer = k->action_layer;
  n.K = scene->camera;
  n.beta = scene->beta;
  const MergeReport merge = scene_stored::DecodeMergeReport(scene->merge_report, scene->id);
  const auto& corrected = merge.X_MapCamera_corrected;
  n.X_MapCamera = engine::ToIsometry(corrected ? UnitPose(*corrected) : StoredPose(*scene));
  for (const MergedModel& used : merge.models_used) n.merged_scenes.push_back(used.scene_id);
  const std::size_t count = static_cast<std::size_t>(n.K.width) * n.K.height;
  n.depth_mm = DecodeAs<std::uint16_t>(k->depth, BlobElement::kU16, count);
  n.background_mm = DecodeAs<std::uint16_t>(k->background, BlobElement::kU16, count);
  return n;
}

}  // namespace anchordb::services
