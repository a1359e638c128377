#pragma once
// Typed requests and results of SceneService (thesis 3.2-3.3). Poses are monogram-named: X_MapCamera is the pose of
// the camera's optical frame (REP-103: z forward, x right, y down) in the map frame. Depths are in metres unless a
// name says otherwise; stamps are nanoseconds since the Unix epoch.
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "engine/scene/merge.h"
#include "engine/scene/merge_candidates.h"
#include "engine/scene/scene_model.h"
#include "schema/types.h"
#include "services/scene/keyframe_listener.h"

namespace anchordb::services {

enum class SceneStatus { kObserving, kClosed, kSuperseded };
enum class KeyframeKind { kBegin, kManual, kSettled, kEnd };
enum class SceneLayerKind { kStatic, kMovable, kDynamic, kReliability };
enum class SceneLayerEncoding { kPng, kRaw };
enum class KeyframeImageKind { kDepth, kBackground };

// The names clients and the database use for these values.
template <typename E>
using EnumNames = std::initializer_list<std::pair<E, const char*>>;
inline const EnumNames<SceneStatus> kSceneStatusNames = {
    {SceneStatus::kObserving, "observing"}, {SceneStatus::kClosed, "closed"}, {SceneStatus::kSuperseded, "superseded"}};
inline const EnumNames<KeyframeKind> kKeyframeKindNames = {{KeyframeKind::kBegin, "begin"}, {KeyframeKind::kManual, "manual"},
                                                           {KeyframeKind::kSettled, "settled"}, {KeyframeKind::kEnd, "end"}};
inline const EnumNames<AnalysisState> kAnalysisStateNames = {{AnalysisState::kPending, "pending"}, {AnalysisState::kDone, "done"},
                                                             {AnalysisState::kFailed, "failed"}, {AnalysisState::kSkipped, "skipped"}};
inline const EnumNames<SceneLayerKind> kSceneLayerNames = {{SceneLayerKind::kStatic, "static"}, {SceneLayerKind::kMovable, "movable"},
                                                           {SceneLayerKind::kDynamic, "dynamic"},
                                                           {SceneLayerKind::kReliability, "reliability"}};
inline const EnumNames<engine::MergeStrategy> kMergeStrategyNames = {{engine::MergeStrategy::kAlgorithm2, "algorithm2"},
                                                                     {engine::MergeStrategy::kNaive, "naive"},
                                                                     {engine::MergeStrategy::kNaiveWithoutIcp, "naive_without_icp"}};
inline const EnumNames<engine::DynamicMode> kDynamicModeNames = {{engine::DynamicMode::kExcludeFromInput, "exclude"},
                                                                 {engine::DynamicMode::kSubtractFromMovable, "subtract"}};

template <typename E>
const char* NameOf(const EnumNames<E>& names, E value) {
  for (const auto& [v, name] : names) {
    if (v == value) return name;
  }
  return "";
}
template <typename E>
std::optional<E> ValueOf(const EnumNames<E>& names, std::string_view name) {
  for (const auto& [v, n] : names) {
    if (name == n) return v;
  }
  return std::nullopt;
}

// Parameters of a scene model, fixed when it is opened.
struct SceneParams {
  engine::SceneModelParams model;  // beta (theta(d) = beta * d) and how dynamic regions enter Algorithm 1
  double depth_scale = 1000.0;     // depth units per metre of the frames (1000: millimetres); (0, 1e6]
};

// Opens a scene model. Errors: kNotFound (map), kUnprocessable (camera outside [1, max_image_side] or fx, fy <= 0;
// beta outside (0, 1]; depth_scale outside (0, 1e6]).
// The localisation uncertainty of a camera pose as two standard deviations (each axis, map frame).
struct PoseSigma {
  double translation_m = 0.0;
  double rotation_rad = 0.0;
};

struct OpenSceneRequest {
  PinholeIntrinsics camera;
  Pose3 X_MapCamera;
  // The pose's uncertainty (issue 13), at most one of the two: sigmas, or a ROS-style 6x6 covariance (36 numbers,
  // row-major, map frame, [tx ty tz rx ry rz]). Neither: the setting's default. Stored with the model; the merge
  // uses it for this model's pose and, later, when this model is an earlier one.
  std::optional<PoseSigma> pose_sigma;
  std::optional<std::vector<double>> pose_covariance;
  SceneParams params;
  bool merge = true;  // merge earlier models of this place with the first frame (3.3.3)
  engine::MergeStrategy merge_strategy = engine::MergeStrategy::kAlgorithm2;
  std::optional<std::int64_t> stamp_ns;  // when the observation started; nullopt: now
};

// What the merge did with one earlier model.
struct MergedModel {
  std::int64_t scene_id = 0;
  bool icp_converged = false;
  bool icp_applied = false;           // the correction was trusted (see engine::MergeParams)
  double fitness_m2 = 0.0;            // after alignment
  double fitness_before_m2 = 0.0;     // before alignment
  Eigen::Vector3d correction_translation_m = Eigen::Vector3d::Zero();
  double correction_rotation_rad = 0.0;
  std::size_t source_points = 0;
  std::size_t target_points = 0;
  std::string icp_verdict;            // why the correction was or was not applied (engine::IcpResult::verdict)
  std::array<double, 6> relative_information{};  // the registration's conditioning (engine::IcpResult)
  int unobservable_directions = 0;
  double mahalanobis2 = 0.0;
  std::array<double, 6> remaining_sigma{};  // sqrt of the remaining covariance's diagonal [m, m, m, rad, rad, rad]
  std::size_t rasterised = 0;         // pixel counts, see engine::MergeModelReport
  std::size_t supported = 0;
  std::size_t replaced_farther = 0;
  std::size_t rear_projected = 0;
  std::size_t filled_unknown = 0;
  std::size_t rejected_fov = 0;
  std::size_t rejected_occlusion = 0;
  std::size_t rejected_neighbourhood = 0;
  std::size_t rejected_uncertain = 0;  // the pose uncertainty at the pixel was beyond what the premises can use
  // The remaining pose uncertainty the premises worked with (median over the model; engine::MergeModelReport) and,
  // when the model was not merged at all, why (empty when it was: the merge is never worse than a fresh model).
  double tolerance_px = 0.0;
  double tolerance_m = 0.0;
  std::string fallback;
};

// The merge of earlier models into a new one (3.3.3-3.3.4): the candidates chosen when it was opened and, once the
// first frame arrived (performed), what each contributed and which models it superseded.
struct MergeReport {
  bool requested = true;
  engine::MergeStrategy strategy = engine::MergeStrategy::kAlgorithm2;
  std::vector<engine::MergeCandidate> candidates;
  std::optional<bool> pending;  // requested: true until the first frame performed the merge
  bool performed = false;
  // When performed:
  std::vector<MergedModel> models_used;
  engine::MergeTiming timing;
  std::vector<std::int64_t> superseded;
  // The camera pose corrected by the best applied ICP correction (X_MapCamera * correction^-1), and whose it was.
  std::optional<Pose3> X_MapCamera_corrected;
  std::optional<std::int64_t> corrected_by_scene;
};

struct SceneStatistics {
  std::size_t movable_pixels = 0;
  std::size_t dynamic_pixels = 0;
  std::size_t known_background_pixels = 0;
};

struct KeyframeRef {
  std::int64_t id = 0;
  KeyframeKind kind = KeyframeKind::kBegin;
  std::int64_t stamp_ns = 0;
};

// A scene model. `state` and `keyframes` are filled by Open and Get; List leaves them empty.
struct SceneInfo {
  std::int64_t id = 0;
  std::string map;
  SceneStatus status = SceneStatus::kObserving;
  PinholeIntrinsics camera;
  Pose3 X_MapCamera;  // as opened
  std::optional<engine::Matrix6d> pose_covariance_map;  // as opened (nullopt: opened before it was stored)
  SceneParams params;
  MergeReport merge;
  std::int64_t started_ns = 0;
  std::optional<std::int64_t> ended_ns;
  std::optional<std::int64_t> last_frame_ns;
  std::optional<std::int64_t> superseded_by;
  std::int64_t persisted_frames = 0;  // frames of the state last written to the database
  struct State {
    std::int64_t frames = 0;  // frames applied
    SceneStatistics statistics;
  };
  std::optional<State> state;
  std::vector<KeyframeRef> keyframes;  // oldest first
};

// Scene models of a map, newest first.
struct SceneListFilter {
  std::optional<Eigen::Vector3d> near_m;  // camera within radius_m of this point (map frame)
  double radius_m = 1.0;
  std::optional<SceneStatus> status;
  int limit = 100;
};

// One depth frame. Errors: kConflict (model not observing), kUnprocessable (size differs from the camera,
// depth_scale outside (0, 1e6]), kInvalidArgument (undecodable image), kNotFound.
struct FrameInput {
  std::string_view body;           // the request body, or the `depth` part of a multipart body
  bool png = true;                 // PNG, else raw little-endian uint16
  std::optional<std::string_view> dynamic_png;  // 8-bit mask
  std::optional<std::int64_t> stamp_ns;         // nullopt: now
  std::optional<double> depth_scale;            // units per metre, overrides the model's
  bool wait_for_analysis = false;               // a keyframe it stores: answer with its analysis (KeyframeListener::Await)
};

struct StoredKeyframe {
  std::int64_t id = 0;
  KeyframeKind kind = KeyframeKind::kBegin;
  std::int64_t action_layer = 0;             // the layer this keyframe opens
  std::optional<KeyframeAnalysisStatus> analysis;  // nullopt without a listener; else pending unless waited for
};

struct FrameResult {
  std::int64_t scene_id = 0;
  std::int64_t frames = 0;            // applied
  std::int64_t persisted_frames = 0;  // durable
  engine::FrameCounts pixels;         // of this frame (after a merge: the merged model's labels)
  std::optional<StoredKeyframe> keyframe;  // the begin or a settled keyframe this frame stored
};

struct KeyframeResult {
  std::int64_t scene_id = 0;
  StoredKeyframe keyframe;
};

struct CloseResult {
  std::int64_t scene_id = 0;
  std::optional<StoredKeyframe> keyframe;  // the end keyframe (none when no frame arrived since loading)
  SceneStatus status = SceneStatus::kClosed;
  std::int64_t frames = 0;
};

// Statistics of a layer (the json format of a layer).
struct SceneLayerSummary {
  SceneLayerKind kind = SceneLayerKind::kStatic;
  int width = 0;  // the model's camera [px]
  int height = 0;
  std::int64_t frames = 0;
  bool cleaned = false;     // movable: noise-cleaned (3.5.1)
  std::size_t pixels = 0;   // movable, dynamic: labelled pixels; static: pixels with a known depth
  double fraction = 0.0;    // movable, dynamic: pixels / image size
  double mean_depth_m = 0.0;  // static, over known pixels (0 without any)
  float max_weight = 0.0f;    // reliability
  double mean_weight = 0.0;   // reliability
};

struct KeyframeInfo {
  std::int64_t id = 0;
  std::int64_t scene_id = 0;
  KeyframeKind kind = KeyframeKind::kBegin;
  std::int64_t stamp_ns = 0;
  int width = 0;
  int height = 0;
  std::int64_t raw_bytes = 0;     // depth and background as uint16
  std::int64_t stored_bytes = 0;  // compressed blobs
  double compression_ratio = 0.0; // stored / raw
  bool pinned = false;
};

}  // namespace anchordb::services
