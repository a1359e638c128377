#pragma once
// SQL for scene models and keyframes.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "schema/types.h"
#include "storage/repositories.h"
#include "storage/connection.h"
#include "storage/scene_merge_report.h"

namespace anchordb::storage {

struct SceneRecord {
  std::int64_t id = 0;
  std::string map_id;
  std::string status = "observing";
  std::optional<std::int64_t> superseded_by;
  PinholeIntrinsics camera;  // width_px, height_px, fx_px, fy_px, cx_px, cy_px
  Pose3 pose;                // the camera's optical frame in the map frame: x_m, y_m, z_m and qx, qy, qz, qw
  // The model's parameters (thesis 3.2): theta(d) = beta * d; how the dynamic mask enters Algorithm 1 ("exclude" or
  // "subtract"); depth units per metre of its frames.
  double beta = 0.03;
  std::string dynamic_mode = "exclude";
  double depth_scale = 1000.0;
  MergeReportRecord merge_report;  // storage/scene_merge_report.h
  std::int64_t started_ns = 0;
  std::optional<std::int64_t> ended_ns;
  std::optional<std::int64_t> last_frame_ns;
  std::int64_t frames = 0;
  std::int64_t state_version = 0;
  std::optional<std::int64_t> forgotten_ns;  // forgetting dropped the state of this superseded model
  // The camera pose's covariance (map frame, 6x6 row-major, ROS order [tx ty tz rx ry rz], m and rad); nullopt: not
  // given or unreadable (the default applies). Stored in the blob envelope (f64 {6, 6}, migration 0018); a row of
  // an earlier schema holds a JSON array of 36 numbers, which still reads.
  std::optional<std::array<double, 36>> pose_covariance;
  // State blobs; empty when not loaded or never persisted.
  std::string background;
  std::string weight;
  std::string labels;
};

// Inserts and returns the new id.
std::int64_t InsertScene(Connection& c, const SceneRecord& scene);
std::optional<SceneRecord> FindScene(Connection& c, const std::string& map_id, std::int64_t id, bool with_state);
// Scenes of a map, newest first; near: camera within radius_m of the point (R*Tree, then exact).
struct SceneFilter {
  std::optional<Eigen::Vector3d> near_m;
  double radius_m = 0.0;
  std::optional<std::string> status;
  int limit = 100;
};
std::vector<SceneRecord> ListScenes(Connection& c, const std::string& map_id, const SceneFilter& filter);
// Persists the state (and frames, last_frame_ns, state_version); kConflict if the stored version is not `expected`.
void UpdateSceneState(Connection& c, const SceneRecord& scene, std::int64_t expected_state_version);
void UpdateSceneStatus(Connection& c, std::int64_t id, const std::string& status, std::optional<std::int64_t> ended_ns,
                       std::optional<std::int64_t> superseded_by);

struct KeyframeRecord {
  std::int64_t id = 0;
  std::string map_id;
  std::int64_t scene_id = 0;
  std::string kind;
  std::int64_t stamp_ns = 0;
  int width = 0, height = 0;
  std::string depth;       // blob
  std::string background;  // blob
  std::int64_t raw_bytes = 0;
  std::int64_t stored_bytes = 0;
  bool pinned = false;
  std::int64_t action_layer = 0;  // the layer this keyframe opens (0 for the begin keyframe)
  double relevance = 0.0;
};
std::int64_t InsertKeyframe(Connection& c, const KeyframeRecord& keyframe);
std::optional<KeyframeRecord> FindKeyframe(Connection& c, const std::string& map_id, std::int64_t id, bool with_images);
std::vector<KeyframeRecord> ListKeyframes(Connection& c, const std::string& map_id, std::int64_t scene_id);

}  // namespace anchordb::storage
