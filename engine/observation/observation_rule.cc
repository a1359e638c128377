#include "engine/observation/observation_rule.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace anchordb::engine {

namespace {

void RequirePositive(double value, const char* name) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    throw std::invalid_argument(std::string("observation rule: ") + name + " must be a positive number");
  }
}

}  // namespace

void ValidateObservationRuleParams(const ObservationRuleParams& params) {
  RequirePositive(params.still_window_s, "still_window_s");
  RequirePositive(params.still_translation_m, "still_translation_m");
  RequirePositive(params.still_rotation_rad, "still_rotation_rad");
  RequirePositive(params.leave_translation_m, "leave_translation_m");
  RequirePositive(params.leave_rotation_rad, "leave_rotation_rad");
  RequirePositive(params.max_gap_s, "max_gap_s");
  if (!(params.min_dwell_s >= 0.0) || !std::isfinite(params.min_dwell_s)) {
    throw std::invalid_argument("observation rule: min_dwell_s must be zero or more");
  }
  if (params.leave_translation_m < params.still_translation_m) {
    throw std::invalid_argument("observation rule: leave_translation_m must not be below still_translation_m");
  }
  if (params.leave_rotation_rad < params.still_rotation_rad) {
    throw std::invalid_argument("observation rule: leave_rotation_rad must not be below still_rotation_rad");
  }
}

std::string ObservationCloseReasonName(ObservationCloseReason reason) {
  switch (reason) {
    case ObservationCloseReason::kNone: return "none";
    case ObservationCloseReason::kCameraLeft: return "camera_left";
    case ObservationCloseReason::kTimeGap: return "time_gap";
    case ObservationCloseReason::kEndOfStream: return "end_of_stream";
  }
  return "unknown";
}

double PoseDistanceM(const Eigen::Isometry3d& X_A, const Eigen::Isometry3d& X_B) {
  return (X_A.translation() - X_B.translation()).norm();
}

double PoseAngleRad(const Eigen::Isometry3d& X_A, const Eigen::Isometry3d& X_B) {
  const Eigen::Matrix3d R_AB = X_A.linear().transpose() * X_B.linear();
  // The angle from the trace, clamped against rounding (a rotation's trace lies in [-1, 3]).
  const double cos_angle = std::clamp((R_AB.trace() - 1.0) / 2.0, -1.0, 1.0);
  return std::acos(cos_angle);
}

ObservationRule::ObservationRule(const ObservationRuleParams& params) : params_(params) {
  ValidateObservationRuleParams(params_);
}

bool ObservationRule::StillNow(const Eigen::Isometry3d& X_MapCamera) const {
  for (const Pose& pose : window_) {
    if (PoseDistanceM(pose.X_MapCamera, X_MapCamera) > params_.still_translation_m ||
        PoseAngleRad(pose.X_MapCamera, X_MapCamera) > params_.still_rotation_rad) {
      return false;
    }
  }
  return true;
}

bool ObservationRule::Left(const Eigen::Isometry3d& X_MapCamera) const {
  return PoseDistanceM(*anchor_, X_MapCamera) > params_.leave_translation_m ||
         PoseAngleRad(*anchor_, X_MapCamera) > params_.leave_rotation_rad;
}

void ObservationRule::Close(ObservationCloseReason reason) {
  anchor_.reset();
  if (reason == ObservationCloseReason::kCameraLeft) ++counts_.closed_left;
  if (reason == ObservationCloseReason::kTimeGap) ++counts_.closed_gap;
  if (reason == ObservationCloseReason::kEndOfStream) ++counts_.closed_end;
}

ObservationStep ObservationRule::OnFrame(double stamp_s, const Eigen::Isometry3d& X_MapCamera) {
  ObservationStep step;
  ++counts_.frames;
  if (!std::isfinite(stamp_s) || (last_stamp_s_ && stamp_s <= *last_stamp_s_)) {
    step.ignored = true;
    ++counts_.ignored;
    return step;
  }
  if (last_stamp_s_ && stamp_s - *last_stamp_s_ > params_.max_gap_s) {
    // A pause of the stream: what came before says nothing about where the camera is now.
    if (anchor_) {
      step.close_reason = ObservationCloseReason::kTimeGap;
      Close(step.close_reason);
    }
    window_.clear();
    still_since_s_.reset();
  }
  last_stamp_s_ = stamp_s;
  if (anchor_ && Left(X_MapCamera)) {
    step.close_reason = ObservationCloseReason::kCameraLeft;
    Close(step.close_reason);
  }
  while (!window_.empty() && window_.front().stamp_s < stamp_s - params_.still_window_s) window_.pop_front();
  const bool still = StillNow(X_MapCamera);
  window_.push_back({stamp_s, X_MapCamera});
  if (!still) {
    still_since_s_.reset();
  } else if (!still_since_s_) {
    still_since_s_ = stamp_s;
  }
  // A model opens only after the camera left the previous one (a close this frame) or when none was open.
  if (!anchor_ && still && stamp_s - *still_since_s_ >= params_.min_dwell_s &&
      step.close_reason != ObservationCloseReason::kCameraLeft) {
    anchor_ = X_MapCamera;
    step.open = true;
    ++counts_.opened;
  }
  if (anchor_) {
    step.feed = true;
    ++counts_.fed;
  } else {
    ++counts_.moving;
  }
  return step;
}

ObservationCloseReason ObservationRule::Finish() {
  if (!anchor_) return ObservationCloseReason::kNone;
  Close(ObservationCloseReason::kEndOfStream);
  return ObservationCloseReason::kEndOfStream;
}

}  // namespace anchordb::engine
