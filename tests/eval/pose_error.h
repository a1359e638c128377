#pragma once
// Seeded randomness and injected localisation error for the merge evaluation (portable: no std distributions).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>

#include "tests/eval/merge_cases.h"

namespace anchordb::eval::pose_error {

using Eigen::Isometry3d;
using Eigen::Vector3d;


// Deterministic, portable random numbers (std distributions differ between standard libraries).
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : rng_(seed) {}
  double Uniform(double lo, double hi) {
    const double unit = static_cast<double>(rng_() >> 11) * (1.0 / 9007199254740992.0);
    return lo + (hi - lo) * unit;
  }
  Vector3d UnitVector() {
    const double z = Uniform(-1.0, 1.0), phi = Uniform(0.0, 2.0 * std::numbers::pi);
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    return {r * std::cos(phi), r * std::sin(phi), z};
  }

 private:
  std::mt19937_64 rng_;
};

inline std::uint64_t Mix(std::uint64_t seed, MergeCase c, sim::Setting s, std::uint64_t salt) {
  std::uint64_t x = seed * 0x9E3779B97F4A7C15ULL ^ (static_cast<std::uint64_t>(c) + 1) * 0xD1B54A32D192ED03ULL ^
                    (static_cast<std::uint64_t>(s) + 1) * 0x8CB92BA72F3D8DD7ULL ^ salt * 0xC2B2AE3D27D4EB4FULL;
  x ^= x >> 31;
  return x * 0x94D049BB133111EBULL + salt;
}

// The localisation error of one viewpoint: the stored camera pose is the true one moved by a translation of
// uniform length in [0, max_t] in a random direction and turned about its optical centre by a uniform angle in
// [0, max_r] about a random axis.
inline Isometry3d WithPoseError(const Isometry3d& X_true, Rng& rng, double max_t, double max_r) {
  const Vector3d t = rng.UnitVector() * rng.Uniform(0.0, max_t);
  const Vector3d axis = rng.UnitVector();
  const double angle = rng.Uniform(0.0, max_r);
  Isometry3d X = X_true;
  X.linear() = Eigen::AngleAxisd(angle, axis).toRotationMatrix() * X_true.linear();
  X.translation() = X_true.translation() + t;
  return X;
}

inline double RotationAngle(const Eigen::Matrix3d& R) { return Eigen::AngleAxisd(R).angle(); }

}  // namespace anchordb::eval::pose_error
