#include "sim/lost_key_scenario.h"

#include <Eigen/Geometry>
#include <httplib.h>

#include <chrono>
#include <thread>

#include "sim/apartment.h"
#include "sim/renderer.h"
#include "sim/scenario_driver.h"

namespace anchordb::sim {
namespace {

using nlohmann::json;

constexpr int kObject1 = 201, kObject2Shelf = 21 /* the SE setting's box */, kObject2AtA = 202, kObject3 = 203,
              kObject3b = 204;

}  // namespace

LostKeyResult RunLostKeyScenario(httplib::Client& client, const LostKeyOptions& o) {
  ScenarioDriver d(client, o.map, o.log);
  if (o.kind_sensor) d.SetSensor(KindSensor());
  Rng rng(o.seed * 7919 + 17);
  LostKeyResult result;
  const std::string maps = "/v1/maps/" + o.map;
  if (o.create_map) d.Call("POST", "/v1/maps", {{"id", o.map}, {"name", "simulated apartment"}}, 201);

  // Place A: the tabletop, cleared of its small objects. Place B: the shelf, 10 m away in the map (X_Map_B).
  SettingScene a = MakeSetting(Setting::kTA, o.seed);
  for (int id : a.movable_ids) RemoveObject(a.scene, id);
  for (int id : {a.thin_object_id, a.tall_object_id}) RemoveObject(a.scene, id);
  SettingScene b = MakeSetting(Setting::kSE, o.seed);
  const Eigen::Isometry3d X_Map_B(Eigen::Translation3d(0.0, 10.0, 0.0));
  const auto [table_lo, table_hi] = Bounds(a.scene, 10);
  const auto [shelf_lo, shelf_hi] = Bounds(b.scene, 10);
  const Eigen::Vector3d shelf_c = X_Map_B * (0.5 * (shelf_lo + shelf_hi));
  result.table_centre_m = 0.5 * (table_lo + table_hi).head<2>();
  result.table_extent_m = (table_hi - table_lo).head<2>();
  if (o.enter_furniture) {
    d.Call("POST", maps + "/instances", {{"kind", "furniture"}, {"label", "table"}, {"position", {0.5 * (table_lo + table_hi).x(), 0.5 * (table_lo + table_hi).y(), 0.5 * (table_lo + table_hi).z()}},
                                         {"extent", {(table_hi - table_lo).x(), (table_hi - table_lo).y(), (table_hi - table_lo).z()}}}, 201);
    d.Call("POST", maps + "/instances", {{"kind", "furniture"}, {"label", "shelf"}, {"position", {shelf_c.x(), shelf_c.y(), shelf_c.z()}},
                                         {"extent", {(shelf_hi - shelf_lo).x(), (shelf_hi - shelf_lo).y(), (shelf_hi - shelf_lo).z()}}}, 201);
  }

  const Eigen::Vector3d top = a.surface_point_m;
  const auto on_table = [&](double dx, double dy, double height) {
    return Eigen::Vector3d(top.x() + dx + rng.Uniform(-0.03, 0.03), top.y() + dy + rng.Uniform(-0.03, 0.03), top.z() + 0.5 * height);
  };
  // Object 1: a box of varied size. Object 3: flat (a book, a tray) or tall (a bottle), so it is not mistaken for
  // object 2 by size. Object 2 is the shelf's box; at A it keeps its size.
  const Eigen::Vector3d size1(rng.Uniform(0.08, 0.14), rng.Uniform(0.08, 0.14), rng.Uniform(0.06, 0.14));
  const bool flat3 = rng.Uniform(0, 1) < 0.5;
  const Eigen::Vector3d size3 = flat3 ? Eigen::Vector3d(rng.Uniform(0.16, 0.22), rng.Uniform(0.12, 0.16), rng.Uniform(0.025, 0.04))
                                      : Eigen::Vector3d(rng.Uniform(0.05, 0.07), rng.Uniform(0.05, 0.07), rng.Uniform(0.24, 0.30));
  const bool two_meanwhile = rng.Uniform(0, 1) < 0.5;  // "the operator placed randomly one or two objects"
  const Eigen::Vector3d size3b(rng.Uniform(0.16, 0.22), rng.Uniform(0.12, 0.16), rng.Uniform(0.025, 0.04));
  const auto [box_lo, box_hi] = Bounds(b.scene, kObject2Shelf);
  const Eigen::Vector3d size2 = box_hi - box_lo;
  const Eigen::Vector3d c1 = on_table(-0.15, -0.32, size1.z()), c3 = on_table(-0.12, 0.30, size3.z()),
                        c3b = on_table(0.20, 0.36, size3b.z()), c2 = on_table(0.08, -0.02, size2.z());
  const double yaw1 = rng.Uniform(-0.5, 0.5), yaw3 = rng.Uniform(-0.5, 0.5);

  const int n = o.frames_per_visit, put = n * 3 / 8, leave = n / 2;  // person from n/4 to n/2, object at 3n/8
  const Primitive person_a = PersonBeside(top, a.X_WorldCameraA);
  const std::int64_t t1 = o.start_ns, t2 = t1 + 120'000'000'000LL, t3 = t1 + 900'000'000'000LL;

  // 1. Object 1 brought to A.
  Scene a1 = a.scene;
  d.Observe("visit 1 (place A, viewpoint 1)", a.X_WorldCameraA, a.X_WorldCameraA, n, [&](int i) {
    Scene s = a1;
    if (i >= put) AddBox(s, kObject1, "object 1", c1, size1, yaw1);
    const bool person = i >= n / 4 && i < leave;
    if (person) s.objects.push_back({kPersonId, "person", "person"}), s.primitives.push_back(person_a);
    return std::make_pair(s, person);
  }, t1, o.seed * 10 + 1);
  result.expected.push_back({"added", "observed", "A", "object 1", c1});

  // 2. Object 2 taken from B.
  const Eigen::Vector3d c2_b = X_Map_B * Centre(b.scene, kObject2Shelf);
  const Primitive person_b = PersonBeside(b.surface_point_m, b.X_WorldCameraA);
  d.Observe("visit 2 (place B)", b.X_WorldCameraA, X_Map_B * b.X_WorldCameraA, n, [&](int i) {
    Scene s = b.scene;
    if (i >= put) RemoveObject(s, kObject2Shelf);
    const bool person = i >= n / 4 && i < leave;
    if (person) s.objects.push_back({kPersonId, "person", "person"}), s.primitives.push_back(person_b);
    return std::make_pair(s, person);
  }, t2, o.seed * 10 + 2);
  result.expected.push_back({"removed", "observed", "B", "object 2", c2_b});
  result.keys_before_m = c2_b;
  // The person says what they took: the removal at B is labelled "keys".
  const json removals = d.Call("GET", maps + "/events?type=removed&since=" + std::to_string(t2), json(), 200);
  std::int64_t keys_event = 0;
  double nearest = 1e9;
  for (const json& e : removals["events"]) {
    const auto& c = e["details"]["segment"]["centroid_m"];
    const double dist = (Eigen::Vector3d(c[0], c[1], c[2]) - c2_b).norm();
    if (dist < nearest) nearest = dist, keys_event = e["id"].get<std::int64_t>();
  }
  if (keys_event != 0) {
    d.Call("POST", maps + "/events/" + std::to_string(keys_event) + ":label", {{"label", "keys"}}, 200);
    d.Log("dialog: \"I am taking my keys\" -> event " + std::to_string(keys_event) + " labelled 'keys'");
  } else {
    d.Log("the removal at place B was not detected; nothing to label");
  }

  // 3. Meanwhile, object 3 (and maybe another) appears at A. 4. Object 2 brought to A, seen from viewpoint B of A
  // with a pose error.
  Scene a2 = a1;
  AddBox(a2, kObject1, "object 1", c1, size1, yaw1);
  AddBox(a2, kObject3, "object 3", c3, size3, yaw3);
  result.expected.push_back({"added", "meanwhile", "A", "object 3", c3});
  if (two_meanwhile) {
    AddBox(a2, kObject3b, "object 3b", c3b, size3b, 0.0);
    result.expected.push_back({"added", "meanwhile", "A", "object 3b", c3b});
  }
  const Eigen::Vector3d axis = Eigen::Vector3d(rng.Uniform(-1, 1), rng.Uniform(-1, 1), rng.Uniform(-1, 1)).normalized();
  const Eigen::Vector3d shift = Eigen::Vector3d(rng.Uniform(-1, 1), rng.Uniform(-1, 1), rng.Uniform(-1, 1)).normalized() *
                                rng.Uniform(0.0, o.pose_error_max_m);
  const Eigen::Isometry3d error = Eigen::Translation3d(shift) * Eigen::AngleAxisd(rng.Uniform(0.0, o.pose_error_max_rad), axis);
  const Primitive person_a2 = PersonBeside(top, a.X_WorldCameraB);
  d.Observe("visit 3 (place A, viewpoint 2)", a.X_WorldCameraB, error * a.X_WorldCameraB, n, [&](int i) {
    Scene s = a2;
    if (i >= put) AddBox(s, kObject2AtA, "object 2", c2, size2, 0.0);
    const bool person = i >= n / 4 && i < leave;
    if (person) s.objects.push_back({kPersonId, "person", "person"}), s.primitives.push_back(person_a2);
    return std::make_pair(s, person);
  }, t3, o.seed * 10 + 3);
  result.expected.push_back({"added", "observed", "A", "object 2", c2});
  result.keys_true_m = c2;

  if (o.segment_furniture) {
    json request = json::object();
    if (!o.segmentation_params.empty()) request["params"] = o.segmentation_params;
    const json ticket = d.Call("POST", maps + "/furniture:segment", request, 202);
    const std::string path = "/v1/jobs/" + std::to_string(ticket["job"].get<std::int64_t>());
    for (int i = 0; i < 3000; ++i) {
      result.segmentation = d.Call("GET", path, json(), 200);
      const std::string status = result.segmentation.value("status", "");
      if (status == "succeeded" || status == "failed") break;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    d.Log("segmentation: " + result.segmentation.value("status", std::string("?")));
  }
  result.events = d.Call("GET", maps + "/events?limit=1000", json(), 200)["events"];
  auto r = client.Get(maps + "/where?label=keys");
  result.where = r ? json::parse(r->body, nullptr, false) : json();
  r = client.Get(maps + "/where?label=keys&at=" + std::to_string(t2 + 600'000'000'000LL / 2));
  result.past_where = r ? json::parse(r->body, nullptr, false) : json();
  return result;
}

EventScore ScoreEvents(const LostKeyResult& result, double tolerance_m) {
  EventScore score;
  std::vector<bool> matched(result.expected.size(), false);
  for (const json& e : result.events) {
    const std::string type = e["type"];
    if (type == "labelled") continue;
    const std::string detection = e["detection"];
    const auto& c = e["details"]["segment"]["centroid_m"];
    const Eigen::Vector3d p(c[0], c[1], c[2]);
    const std::string place = p.y() > 5.0 ? "B" : "A";
    const std::string as = type == "moved" ? "added" : type;
    int best = -1;
    double best_d = tolerance_m;
    for (std::size_t k = 0; k < result.expected.size(); ++k) {
      const ExpectedEvent& x = result.expected[k];
      if (matched[k] || x.type != as || x.detection != detection || x.place != place) continue;
      const double dist = (x.centre_m - p).norm();
      if (dist <= best_d) best_d = dist, best = static_cast<int>(k);
    }
    EventCounts& counts = detection == "meanwhile" ? score.meanwhile : score.observed;
    if (best >= 0) matched[static_cast<std::size_t>(best)] = true, ++counts.tp;
    else ++counts.fp;
  }
  for (std::size_t k = 0; k < result.expected.size(); ++k) {
    if (!matched[k]) ++(result.expected[k].detection == "meanwhile" ? score.meanwhile : score.observed).fn;
  }
  return score;
}

}  // namespace anchordb::sim
