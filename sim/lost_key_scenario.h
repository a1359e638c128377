#pragma once
// The event-detection scenario of thesis 3.5.2 (and the lost-key demonstration of 1.4 / 3.5.3), driven against a
// running anchordb server over HTTP with rendered depth frames:
//   1. a person brings object 1 to place A (a table)           -> added at A, observed
//   2. the person takes object 2 from place B (a shelf)        -> removed from B, observed; labelled "keys"
//   3. meanwhile object 3 (sometimes a second one) appears at A -> added at A, meanwhile (found through the merge)
//   4. the person brings object 2 to A, seen from viewpoint B  -> added at A, observed (inferred: the keys moved)
// Seeded variation: object sizes and positions, the second viewpoint of A (40-50 cm and 30-40 deg from the
// first, the SettingScene's viewpoint B) and a camera pose error on the viewpoint change (up to 5 cm, 3 deg).
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace httplib {
class Client;
}

namespace anchordb::sim {

struct LostKeyOptions {
  std::uint64_t seed = 1;
  std::string map = "home";
  int frames_per_visit = 24;
  double pose_error_max_m = 0.05;
  double pose_error_max_rad = 0.0524;  // 3 deg
  std::int64_t start_ns = 1'767'225'600'000'000'000;  // 2026-01-01; the scenario spans a few simulated minutes
  bool create_map = true;
  bool kind_sensor = false;  // render with sim::KindSensor() (the sensor before issue 13) instead of the default
  // Furniture: the client enters the table and the shelf as instances (the default), or nobody does and, with
  // `segment_furniture`, the robot finds them itself (POST .../furniture:segment over its keyframes, issue 16)
  // before the where-is questions are asked.
  bool enter_furniture = true;
  bool segment_furniture = false;
  nlohmann::json segmentation_params = nlohmann::json::object();  // the segmentation request's "params" (empty: defaults)
  std::function<void(const std::string&)> log;  // progress lines (the demo prints them)
};

struct ExpectedEvent {
  std::string type;       // added | removed
  std::string detection;  // observed | meanwhile
  std::string place;      // A | B
  std::string object;     // "object 1", ...
  Eigen::Vector3d centre_m = Eigen::Vector3d::Zero();  // true centre in the map frame
};

struct LostKeyResult {
  std::vector<ExpectedEvent> expected;
  nlohmann::json events;          // GET /events after the scenario
  nlohmann::json where;           // GET /where?label=keys
  nlohmann::json past_where;      // GET /where?label=keys&at=<between steps 2 and 4>
  Eigen::Vector3d keys_true_m = Eigen::Vector3d::Zero();  // where object 2 really is at the end (at A)
  Eigen::Vector3d keys_before_m = Eigen::Vector3d::Zero();  // where it was before (at B)
  std::string keys_furniture = "table";
  Eigen::Vector2d table_centre_m = Eigen::Vector2d::Zero();  // the true table footprint at A
  Eigen::Vector2d table_extent_m = Eigen::Vector2d::Zero();
  nlohmann::json segmentation;  // the segmentation job (segment_furniture), as GET /v1/jobs/{id} shows it at the end
};

// Throws std::runtime_error when the server answers a request with an unexpected status.
LostKeyResult RunLostKeyScenario(httplib::Client& client, const LostKeyOptions& options);

// Expected vs detected ('labelled' events are not change events). A detected event is a true positive when it has
// the expected type (moved counts as added at its destination), detection and place and lies within
// `tolerance_m` of the object's true centre; each expected event is matched at most once.
struct EventCounts {
  int tp = 0, fp = 0, fn = 0;
};
struct EventScore {
  EventCounts observed, meanwhile;
  EventCounts Total() const { return {observed.tp + meanwhile.tp, observed.fp + meanwhile.fp, observed.fn + meanwhile.fn}; }
};
EventScore ScoreEvents(const LostKeyResult& result, double tolerance_m = 0.15);

}  // namespace anchordb::sim
