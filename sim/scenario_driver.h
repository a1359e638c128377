#pragma once
// Building blocks of the scenarios driven against a server over HTTP (sim/lost_key_scenario.h, the month of
// forgetting): objects on surfaces, a person beside them, and one observation = open a scene model at a pose,
// post rendered frames (raw depth + the person's mask as the tracker's dynamic layer), close it.
#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "sim/renderer.h"

namespace httplib {
class Client;
}

namespace anchordb::sim {

inline constexpr int kPersonId = 900;

// Deterministic, portable uniform numbers.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : rng_(seed) {}
  double Uniform(double lo, double hi) { return lo + (hi - lo) * (static_cast<double>(rng_() >> 11) * (1.0 / 9007199254740992.0)); }

 private:
  std::mt19937_64 rng_;
};

nlohmann::json CameraJson(const PinholeIntrinsics& K);
nlohmann::json PoseJson(const Eigen::Isometry3d& X);
void AddBox(Scene& scene, int id, const std::string& name, const Eigen::Vector3d& centre, const Eigen::Vector3d& size, double yaw);
// Axis-aligned box around an object's primitives (world frame): {min, max}. Throws for an unknown object.
std::pair<Eigen::Vector3d, Eigen::Vector3d> Bounds(const Scene& scene, int id);
Eigen::Vector3d Centre(const Scene& scene, int id);
// A person (a 1.7 m cylinder) standing beside the surface point, to the side of the camera's view.
Primitive PersonBeside(const Eigen::Vector3d& surface, const Eigen::Isometry3d& X_camera);

class ScenarioDriver {
 public:
  ScenarioDriver(httplib::Client& client, std::string map, std::function<void(const std::string&)> log);
  // Throws std::runtime_error when the status is not `expected`.
  nlohmann::json Call(const std::string& method, const std::string& path, const nlohmann::json& body, int expected);
  void Log(const std::string& line) const;
  // One observation: frames rendered from X_true and reported at X_reported; scene_at(i) gives the scene of frame i
  // and whether the person is in it. Returns the close response.
  nlohmann::json Observe(const std::string& what, const Eigen::Isometry3d& X_true, const Eigen::Isometry3d& X_reported,
                         int frames, const std::function<std::pair<Scene, bool>(int)>& scene_at, std::int64_t start_ns,
                         std::uint64_t seed);
  const std::string& map() const { return map_; }
  // The sensor the frames are rendered with (default: the Kinect-v1-like SensorModel{}).
  void SetSensor(const SensorModel& sensor) { sensor_ = sensor; }

 private:
  httplib::Client& client_;
  std::string map_;
  SensorModel sensor_;
  std::function<void(const std::string&)> log_;
};

}  // namespace anchordb::sim
