#include "sim/scenario_driver.h"

#include <httplib.h>

#include <stdexcept>

#include "sim/apartment.h"
#include "sim/png_writer.h"

namespace anchordb::sim {

using nlohmann::json;

json CameraJson(const PinholeIntrinsics& K) {
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

Primitive PersonBeside(const Eigen::Vector3d& surface, const Eigen::Isometry3d& X_camera) {
  const Eigen::Vector3d view = surface - X_camera.translation();
  const Eigen::Vector3d side = view.cross(Eigen::Vector3d::UnitZ()).normalized();
  Primitive body;
  body.object_id = kPersonId;
  body.shape = Shape::kCylinder;
  body.size_m = {0.2, 0.0, 1.7};
  body.X_WorldPrim.translation() = Eigen::Vector3d(surface.x(), surface.y(), 0.85) + side * 0.85 - view.normalized() * 0.2;
  return body;
}

namespace {

// The tracker's dynamic mask as an 8-bit PNG (0 / 255), written by sim/png_writer.h rather than with the server's
// own codec: the scenario must not share code with what it tests.
std::string MaskPng(const std::vector<std::uint8_t>& mask, int width, int height) {
  std::vector<std::uint8_t> m(mask.size());
  for (std::size_t i = 0; i < mask.size(); ++i) m[i] = mask[i] ? 255 : 0;
  return WritePng(m, width, height, 1, 8);
}

}  // namespace

ScenarioDriver::ScenarioDriver(httplib::Client& client, std::string map, std::function<void(const std::string&)> log)
    : client_(client), map_(std::move(map)), log_(std::move(log)) {}

json ScenarioDriver::Call(const std::string& method, const std::string& path, const json& body, int expected) {
  httplib::Result r = method == "GET" ? client_.Get(path) : client_.Post(path, body.dump(), "application/json");
  if (!r) throw std::runtime_error(method + " " + path + ": no response");
  if (r->status != expected) throw std::runtime_error(method + " " + path + ": " + std::to_string(r->status) + " " + r->body);
  return json::parse(r->body);
}

void ScenarioDriver::Log(const std::string& line) const {
  if (log_) log_(line);
}

json ScenarioDriver::Observe(const std::string& what, const Eigen::Isometry3d& X_true, const Eigen::Isometry3d& X_reported,
                             int frames, const std::function<std::pair<Scene, bool>(int)>& scene_at, std::int64_t start_ns,
                             std::uint64_t seed) {
  const PinholeIntrinsics K = KinectIntrinsics();
  const json opened = Call("POST", "/v1/maps/" + map_ + "/scenes",
                           {{"camera", CameraJson(K)}, {"pose", PoseJson(X_reported)}, {"stamp", start_ns}}, 201);
  const std::string base = "/v1/maps/" + map_ + "/scenes/" + std::to_string(opened["id"].get<std::int64_t>());
  Log(what + ": scene " + std::to_string(opened["id"].get<std::int64_t>()) + " opened, " +
      std::to_string(opened["merge"].value("candidates", json::array()).size()) + " earlier model(s) to merge");
  const SensorModel& sensor = sensor_;
  for (int i = 0; i < frames; ++i) {
    const auto [scene, person] = scene_at(i);
    const Frame f = Render(scene, K, X_true, sensor, seed * 1000 + static_cast<std::uint64_t>(i));
    std::vector<std::uint8_t> mask(f.object_id.size());
    for (std::size_t p = 0; p < mask.size(); ++p) mask[p] = f.object_id[p] == kPersonId;
    httplib::MultipartFormDataItems items = {
        {"depth", std::string(reinterpret_cast<const char*>(f.depth_mm.data()), f.depth_mm.size() * 2), "depth.raw", "application/octet-stream"}};
    if (person) items.push_back({"dynamic", MaskPng(mask, K.width, K.height), "dynamic.png", "image/png"});
    // The driver reads the events each keyframe made: it waits for the keyframe's analysis (queued otherwise).
    const std::string path = base + "/frames?wait_for_analysis=true&stamp=" + std::to_string(start_ns + i * 33'000'000LL);
    auto r = client_.Post(path, items);
    if (!r || r->status != 200) throw std::runtime_error("POST " + path + ": " + (r ? r->body : std::string("no response")));
    const json answer = json::parse(r->body);
    if (answer.contains("analysis")) {
      for (const json& e : answer["analysis"].value("events", json::array())) {
        Log("  frame " + std::to_string(i) + ": event " + e["type"].get<std::string>() + " (" + e["detection"].get<std::string>() + ")");
      }
    }
  }
  const json closed = Call("POST", base + ":close?wait_for_analysis=true", json::object(), 200);
  if (closed.contains("analysis")) {
    for (const json& e : closed["analysis"].value("events", json::array())) {
      Log("  end: event " + e["type"].get<std::string>() + " (" + e["detection"].get<std::string>() + ")");
    }
  }
  return closed;
}

}  // namespace anchordb::sim
