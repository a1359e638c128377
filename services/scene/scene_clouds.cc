// A scene model's layers as point clouds (SPEC 4.9): the static background, or the movable pixels at the depth of
// the latest frame that labelled them, back-projected with the model's camera.
#include "engine/cloud/cloud_io.h"
#include "services/common/cloud_bytes.h"
#include "services/common/stored_pose.h"
#include "engine/scene/projection.h"
#include "services/scene/scene_service.h"
#include "services/scene/scene_service_internal.h"

namespace anchordb::services {

using namespace scene_detail;

ExportedLayer SceneService::LayerCloud(const std::string& map, std::int64_t id, SceneLayerKind layer, bool map_frame,
                                       engine::CloudFormat format) {
  if (layer != SceneLayerKind::kStatic && layer != SceneLayerKind::kMovable) {
    throw Error(ErrorCode::kInvalidArgument, "a scene layer cloud is of layer static or movable", "layer");
  }
  auto [model, lock] = Lock(map, id);
  const engine::SceneModelState& s = model->state;
  const auto& corrected = model->merge.X_MapCamera_corrected;
  const Eigen::Isometry3d X_MapCamera =
      engine::ToIsometry(corrected ? *corrected : StoredPose(model->record));
  const Eigen::Isometry3d X = map_frame ? X_MapCamera : Eigen::Isometry3d::Identity();
  std::vector<Eigen::Vector3f> points;
  if (layer == SceneLayerKind::kStatic) {
    points = engine::BackProject(s.background_m, model->K, X);
  } else {
    // The latest frame's depth: in memory since the model was loaded, else its newest keyframe (the latest frame it
    // kept; a closed model's end keyframe is its last frame).
    std::vector<std::uint16_t> depth_mm = model->last_depth_mm;
    if (depth_mm.empty()) {
      const std::size_t n = static_cast<std::size_t>(model->K.width) * model->K.height;
      store_.Read([&](storage::Connection& c) {
        const std::vector<storage::KeyframeRecord> kfs = storage::ListKeyframes(c, map, id);
        if (kfs.empty()) return 0;
        const auto k = storage::FindKeyframe(c, map, kfs.back().id, true);
        if (k) depth_mm = DecodeAs<std::uint16_t>(k->depth, BlobElement::kU16, n);
        return 0;
      });
    }
    if (depth_mm.size() == s.movable.size()) {
      for (std::size_t i = 0; i < depth_mm.size(); ++i) {
        if (!s.movable[i]) depth_mm[i] = 0;
      }
      points = engine::BackProjectRaw(depth_mm, 1000.0, model->K, X);
    }
  }
  ExportedLayer out = CloudBytes(points, format);
  out.frame = map_frame ? CoordinateFrame::kMap : CoordinateFrame::kCamera;
  out.scene_frames = s.frames;
  return out;
}

}  // namespace anchordb::services
