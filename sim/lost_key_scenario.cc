#include "sim/lost_key_scenario.h"

#include <Eigen/Geometry>
#include <httplib.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "engine/scene/depth_image.h"
#include "sim/apartment.h"
#include "sim/renderer.h"

namespace anchordb::sim {
namespace {

using nlohmann::json;

constexpr int kObject1 = 201, kObject2Shelf = 21 /* the SE setting's box */, kObject2AtA = 202, kObject3 = 203,
              kObject3b = 204, kPerson = 900;

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : rng_(seed) {}
  double Uniform(double lo, double hi) { return lo + (hi - lo) * (static_cast<double>(rng_() >> 11) * (1.0 / 9007199254740992.0)); }

 private:
  std::mt19937_64 rng_;
};

json Camera(const PinholeIntrinsics& K) {
  return {{"width", K.width}, {"height", K.height}, {"fx", K.fx}, {"fy", K.fy}, {"cx", K.cx}, {"cy", K.cy}};
}

json PoseJson(const Eigen::Isometry3d& X) {
  const Eigen::Quaterniond q(X.linear());
  return {{"position", {X.translation().x(), X.translation().y(), X.translation().z()}}, {"orientation", {q.x(), q.y(), q.z(), q.w()}}};
}

void AddBox(Scene& scene, int id, const std::string& name, const Eigen::Vector3d& centre, const Eigen::Vector3d& size, double yaw) {
  scene.objects.push_back({id, name, "movable"});
  Primitive p;
  p.object_id = id;
  p.shape = Shape::kBox;
  p.size_m = size;
  p.X_WorldPrim = Eigen::Translation3d(centre) * Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ());
  scene.primitives.push_back(p);
}

// Axis-aligned box around an object's primitives (world frame): {min, max}.
std::pair<Eigen::Vector3d, Eigen::Vector3d> Bounds(const Scene& scene, int id) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
  for (const Primitive& p : scene.primitives) {
    if (p.object_id != id) continue;
    const Eigen::Vector3d half = p.shape == Shape::kBox ? Eigen::Vector3d(0.5 * p.size_m)
                                                         : Eigen::Vector3d(p.size_m.x(), p.size_m.x(), 0.5 * p.size_m.z());
    for (int corner = 0; corner < 8; ++corner) {
      const Eigen::Vector3d local((corner & 1 ? 1 : -1) * half.x(), (corner & 2 ? 1 : -1) * half.y(), (corner & 4 ? 1 : -1) * half.z());
      const Eigen::Vector3d w = p.shape == Shape::kBox ? Eigen::Vector3d(p.X_WorldPrim * local) : Eigen::Vector3d(p.X_WorldPrim.translation() + local);
      lo = lo.cwiseMin(w);
      hi = hi.cwiseMax(w);
    }
  }
  if (lo.x() > hi.x()) throw std::invalid_argument("no primitives of object " + std::to_string(id));
  return {lo, hi};
}

Eigen::Vector3d Centre(const Scene& scene, int id) {
  const auto [lo, hi] = Bounds(scene, id);
  return 0.5 * (lo + hi);
}

class Driver {
 public:
  Driver(httplib::Client& client, const LostKeyOptions& o) : client_(client), o_(o) {}

  json Call(const std::string& method, const std::string& path, const json& body, int expected) {
    httplib::Result r = method == "GET" ? client_.Get(path) : client_.Post(path, body.dump(), "application/json");
    if (!r) throw std::runtime_error(method + " " + path + ": no response");
    if (r->status != expected) throw std::runtime_error(method + " " + path + ": " + std::to_string(r->status) + " " + r->body);
    return json::parse(r->body);
  }
  void Log(const std::string& line) const {
    if (o_.log) o_.log(line);
  }

  // One observation: frames rendered from X_true, reported at X_reported; `scene_at(i)` is the scene at frame i and
  // whether the person is in view. Returns the close response.
  json Observe(const std::string& what, const Eigen::Isometry3d& X_true, const Eigen::Isometry3d& X_reported,
               const std::function<std::pair<Scene, bool>(int)>& scene_at, std::int64_t start_ns, std::uint64_t seed) {
    const PinholeIntrinsics K = KinectIntrinsics();
    const json opened = Call("POST", "/v1/maps/" + o_.map + "/scenes",
                             {{"camera", Camera(K)}, {"pose", PoseJson(X_reported)}, {"stamp", start_ns}}, 201);
    const std::string base = "/v1/maps/" + o_.map + "/scenes/" + std::to_string(opened["id"].get<std::int64_t>());
    const json& merge = opened["merge"];
    Log(what + ": scene " + std::to_string(opened["id"].get<std::int64_t>()) + " opened, " +
        std::to_string(merge.value("candidates", json::array()).size()) + " earlier model(s) to merge");
    SensorModel sensor;
    for (int i = 0; i < o_.frames_per_visit; ++i) {
      const auto [scene, person] = scene_at(i);
      const Frame f = Render(scene, K, X_true, sensor, seed * 1000 + static_cast<std::uint64_t>(i));
      std::vector<std::uint8_t> mask(f.object_id.size());
      for (std::size_t p = 0; p < mask.size(); ++p) mask[p] = f.object_id[p] == kPerson;
      httplib::MultipartFormDataItems items = {
          {"depth", std::string(reinterpret_cast<const char*>(f.depth_mm.data()), f.depth_mm.size() * 2), "depth.raw", "application/octet-stream"}};
      if (person) items.push_back({"dynamic", engine::EncodeMaskPng(mask, K.width, K.height), "dynamic.png", "image/png"});
      const std::string path = base + "/frames?stamp=" + std::to_string(start_ns + i * 33'000'000LL);
      auto r = client_.Post(path, items);
      if (!r || r->status != 200) throw std::runtime_error("POST " + path + ": " + (r ? r->body : std::string("no response")));
      const json answer = json::parse(r->body);
      if (answer.contains("analysis")) {
        for (const json& e : answer["analysis"].value("events", json::array())) {
          Log("  frame " + std::to_string(i) + ": event " + e["type"].get<std::string>() + " (" + e["detection"].get<std::string>() + ")");
        }
      }
    }
    const json closed = Call("POST", base + ":close", json::object(), 200);
    if (closed.contains("analysis")) {
      for (const json& e : closed["analysis"].value("events", json::array())) {
        Log("  end: event " + e["type"].get<std::string>() + " (" + e["detection"].get<std::string>() + ")");
      }
    }
    return closed;
  }

 private:
  httplib::Client& client_;
  const LostKeyOptions& o_;
};

// A person standing beside the surface, on the side away from the camera's axis.
Primitive PersonBeside(const Eigen::Vector3d& surface, const Eigen::Isometry3d& X_camera) {
  const Eigen::Vector3d view = surface - X_camera.translation();
  const Eigen::Vector3d side = view.cross(Eigen::Vector3d::UnitZ()).normalized();
  Primitive body;
  body.object_id = kPerson;
  body.shape = Shape::kCylinder;
  body.size_m = {0.2, 0.0, 1.7};
  body.X_WorldPrim.translation() = Eigen::Vector3d(surface.x(), surface.y(), 0.85) + side * 0.85 - view.normalized() * 0.2;
  return body;
}

}  // namespace

LostKeyResult RunLostKeyScenario(httplib::Client& client, const LostKeyOptions& o) {
  Driver d(client, o);
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
  d.Call("POST", maps + "/instances", {{"kind", "furniture"}, {"label", "table"}, {"position", {0.5 * (table_lo + table_hi).x(), 0.5 * (table_lo + table_hi).y(), 0.5 * (table_lo + table_hi).z()}},
                                       {"extent", {(table_hi - table_lo).x(), (table_hi - table_lo).y(), (table_hi - table_lo).z()}}}, 201);
  d.Call("POST", maps + "/instances", {{"kind", "furniture"}, {"label", "shelf"}, {"position", {shelf_c.x(), shelf_c.y(), shelf_c.z()}},
                                       {"extent", {(shelf_hi - shelf_lo).x(), (shelf_hi - shelf_lo).y(), (shelf_hi - shelf_lo).z()}}}, 201);

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
  d.Observe("visit 1 (place A, viewpoint 1)", a.X_WorldCameraA, a.X_WorldCameraA, [&](int i) {
    Scene s = a1;
    if (i >= put) AddBox(s, kObject1, "object 1", c1, size1, yaw1);
    const bool person = i >= n / 4 && i < leave;
    if (person) s.objects.push_back({kPerson, "person", "person"}), s.primitives.push_back(person_a);
    return std::make_pair(s, person);
  }, t1, o.seed * 10 + 1);
  result.expected.push_back({"added", "observed", "A", "object 1", c1});

  // 2. Object 2 taken from B.
  const Eigen::Vector3d c2_b = X_Map_B * Centre(b.scene, kObject2Shelf);
  const Primitive person_b = PersonBeside(b.surface_point_m, b.X_WorldCameraA);
  d.Observe("visit 2 (place B)", b.X_WorldCameraA, X_Map_B * b.X_WorldCameraA, [&](int i) {
    Scene s = b.scene;
    if (i >= put) RemoveObject(s, kObject2Shelf);
    const bool person = i >= n / 4 && i < leave;
    if (person) s.objects.push_back({kPerson, "person", "person"}), s.primitives.push_back(person_b);
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
  d.Observe("visit 3 (place A, viewpoint 2)", a.X_WorldCameraB, error * a.X_WorldCameraB, [&](int i) {
    Scene s = a2;
    if (i >= put) AddBox(s, kObject2AtA, "object 2", c2, size2, 0.0);
    const bool person = i >= n / 4 && i < leave;
    if (person) s.objects.push_back({kPerson, "person", "person"}), s.primitives.push_back(person_a2);
    return std::make_pair(s, person);
  }, t3, o.seed * 10 + 3);
  result.expected.push_back({"added", "observed", "A", "object 2", c2});
  result.keys_true_m = c2;

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
