#include "services/scene/scene_pose_covariance.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <numbers>

#include "schema/error.h"

namespace anchordb::services::scene_pose {

engine::Matrix6d Resolve(const OpenSceneRequest& request, const MergeSettings& settings) {
  if (request.pose_sigma && request.pose_covariance) {
    throw Error(ErrorCode::kUnprocessable, "give pose_sigma or pose_covariance, not both", "pose_covariance");
  }
  if (request.pose_sigma) {
    const PoseSigma& s = *request.pose_sigma;
    const auto check = [](double v, double hi, const char* field, const char* unit) {
      if (!std::isfinite(v)) throw Error(ErrorCode::kInvalidArgument, std::string(field) + " must be a finite number", field);
      if (v < 0.0 || v > hi) {
        throw Error(ErrorCode::kUnprocessable, std::string(field) + " must be in [0, " + unit + "]", field);
      }
    };
    check(s.translation_m, 10.0, "pose_sigma.translation_m", "10] m");
    check(s.rotation_rad, std::numbers::pi, "pose_sigma.rotation_rad", "pi] rad");
    return engine::PoseCovarianceFromSigma(s.translation_m, s.rotation_rad);
  }
  if (request.pose_covariance) {
    const std::vector<double>& v = *request.pose_covariance;
    if (v.size() != 36) {
      throw Error(ErrorCode::kUnprocessable,
                  "pose_covariance must be 36 numbers (6x6, row-major), not " + std::to_string(v.size()), "pose_covariance");
    }
    engine::Matrix6d c;
    double largest = 0.0;
    for (int i = 0; i < 36; ++i) {
      if (!std::isfinite(v[i])) {
        throw Error(ErrorCode::kInvalidArgument, "pose_covariance[" + std::to_string(i) + "] must be a finite number",
                    "pose_covariance");
      }
      c(i / 6, i % 6) = v[i];
      largest = std::max(largest, std::abs(v[i]));
    }
    const double tolerance = 1e-9 * std::max(1.0, largest);
    for (int i = 0; i < 6; ++i) {
      for (int j = i + 1; j < 6; ++j) {
        if (std::abs(c(i, j) - c(j, i)) > tolerance) {
          throw Error(ErrorCode::kUnprocessable,
                      "pose_covariance must be symmetric: element [" + std::to_string(i) + "][" + std::to_string(j) +
                          "] differs from [" + std::to_string(j) + "][" + std::to_string(i) + "]",
                      "pose_covariance");
        }
      }
    }
    const Eigen::SelfAdjointEigenSolver<engine::Matrix6d> eig(c);
    if (eig.eigenvalues().minCoeff() < -tolerance) {
      throw Error(ErrorCode::kUnprocessable, "pose_covariance must be positive semi-definite (its smallest eigenvalue is " +
                                                 std::to_string(eig.eigenvalues().minCoeff()) + ")",
                  "pose_covariance");
    }
    if (c.diagonal().head<3>().maxCoeff() > 100.0 || c.diagonal().tail<3>().maxCoeff() > std::numbers::pi * std::numbers::pi) {
      throw Error(ErrorCode::kUnprocessable, "pose_covariance variances must be at most 100 m^2 and pi^2 rad^2",
                  "pose_covariance");
    }
    return 0.5 * (c + c.transpose());
  }
  return engine::PoseCovarianceFromSigma(settings.pose_sigma_translation_m, settings.pose_sigma_rotation_rad);
}

std::array<double, 36> RowMajor(const engine::Matrix6d& covariance) {
  std::array<double, 36> out;
  for (int i = 0; i < 36; ++i) out[i] = covariance(i / 6, i % 6);
  return out;
}

std::optional<engine::Matrix6d> FromStored(const std::optional<std::array<double, 36>>& row_major) {
  if (!row_major) return std::nullopt;
  engine::Matrix6d c;
  for (int i = 0; i < 36; ++i) c(i / 6, i % 6) = (*row_major)[i];
  return c;
}

engine::Matrix6d StoredOrDefault(const std::optional<std::array<double, 36>>& row_major, const MergeSettings& settings) {
  return FromStored(row_major).value_or(
      engine::PoseCovarianceFromSigma(settings.pose_sigma_translation_m, settings.pose_sigma_rotation_rad));
}

}  // namespace anchordb::services::scene_pose
