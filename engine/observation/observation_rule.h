#pragma once
// The observation rule (issue 32): from a stream of depth frames with camera poses, decide when the camera holds
// still at a place, open a scene model there, feed it the frames while the camera stays, and close it when the camera
// leaves or the stream pauses. Pure: fed one frame's stamp and pose at a time; no clock, no I/O. The rosbag importer
// and the ROS bridge both drive scene models with it, so a bag imported and the same bag played give the same models.
// C++17-clean (header and .cc): the ROS bridge compiles it as C++17, since ROS 1's generated messages need that.
#include <cstdint>
#include <deque>
#include <optional>
#include <string>

#include <Eigen/Geometry>

namespace anchordb::engine {

// Settings of the rule. Every distance is the camera's optical centre in the map frame [m]; every angle the rotation
// between two camera orientations [rad]; every duration in the stream's own stamps [s].
struct ObservationRuleParams {
  double still_window_s = 0.5;        // the camera is still when every pose of the last still_window_s ...
  double still_translation_m = 0.03;  // ... lies within this distance of the current pose ...
  double still_rotation_rad = 0.035;  // ... and within this rotation of it (2 degrees)
  double min_dwell_s = 1.0;           // still this long (without interruption) before a scene model opens
  double leave_translation_m = 0.15;  // an open model closes when the camera is farther than this from where it opened
  double leave_rotation_rad = 0.17;   // ... or turned more than this (10 degrees) from the opening orientation
  double max_gap_s = 1.0;             // a gap between two frames longer than this closes the open model
};

// Throws std::invalid_argument naming the first setting that is negative, zero where it must be positive, or
// inconsistent (a leave threshold below its still threshold).
void ValidateObservationRuleParams(const ObservationRuleParams& params);

enum class ObservationCloseReason : std::uint8_t {
  kNone = 0,
  kCameraLeft,  // the camera moved or turned beyond the leave thresholds from the opening pose
  kTimeGap,     // no frame for longer than max_gap_s
  kEndOfStream  // Finish() with a model open
};
std::string ObservationCloseReasonName(ObservationCloseReason reason);

// What the caller does with one frame, in this order: close the open model (close_reason != kNone), then open a new
// one at this frame's pose (open), then apply this frame to the open model (feed).
struct ObservationStep {
  ObservationCloseReason close_reason = ObservationCloseReason::kNone;
  bool open = false;
  bool feed = false;
  bool ignored = false;  // the stamp is not after the previous frame's: nothing changes, the frame is not used
};

// Counts over the stream so far.
struct ObservationRuleCounts {
  std::int64_t frames = 0;        // frames offered (ignored ones included)
  std::int64_t fed = 0;           // frames fed to a model
  std::int64_t moving = 0;        // frames dropped because no model was open (camera moving or dwelling)
  std::int64_t ignored = 0;       // frames whose stamp did not advance
  std::int64_t opened = 0;        // scene models opened
  std::int64_t closed_left = 0;   // closed because the camera left
  std::int64_t closed_gap = 0;    // closed because of a time gap
  std::int64_t closed_end = 0;    // closed by Finish()
};

class ObservationRule {
 public:
  // Throws std::invalid_argument on bad params (see ValidateObservationRuleParams).
  explicit ObservationRule(const ObservationRuleParams& params = {});

  // Offers one frame: its stamp [s] and the camera's pose in the map frame (X_MapCamera). Stamps must increase; a
  // frame whose stamp does not is ignored.
  ObservationStep OnFrame(double stamp_s, const Eigen::Isometry3d& X_MapCamera);

  // Ends the stream: kEndOfStream when a model is open (the caller closes it), kNone otherwise.
  ObservationCloseReason Finish();

  bool model_open() const { return anchor_.has_value(); }
  // The pose at which the open model opened (the first frame fed to it); nullopt when none is open.
  const std::optional<Eigen::Isometry3d>& X_MapAnchor() const { return anchor_; }
  const ObservationRuleCounts& counts() const { return counts_; }
  const ObservationRuleParams& params() const { return params_; }

 private:
  struct Pose {
    double stamp_s = 0.0;
    Eigen::Isometry3d X_MapCamera = Eigen::Isometry3d::Identity();
  };
  bool StillNow(const Eigen::Isometry3d& X_MapCamera) const;
  bool Left(const Eigen::Isometry3d& X_MapCamera) const;
  void Close(ObservationCloseReason reason);

  ObservationRuleParams params_;
  ObservationRuleCounts counts_;
  std::deque<Pose> window_;               // the frames of the last still_window_s, oldest first
  std::optional<double> last_stamp_s_;    // the previous accepted frame's stamp
  std::optional<double> still_since_s_;   // the stamp at which the current still run began
  std::optional<Eigen::Isometry3d> anchor_;
};

// Translation [m] and rotation [rad] between two poses of the same frame.
double PoseDistanceM(const Eigen::Isometry3d& X_A, const Eigen::Isometry3d& X_B);
double PoseAngleRad(const Eigen::Isometry3d& X_A, const Eigen::Isometry3d& X_B);

}  // namespace anchordb::engine
