// Scene editing and the JSON scene description of sim/renderer.h.
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <set>
#include <stdexcept>
#include <string>
#include <string_view>

#include "sim/renderer.h"

namespace anchordb::sim {
namespace {

using Json = nlohmann::json;

[[noreturn]] void Fail(const std::string& path, const std::string& what) {
  throw std::invalid_argument("scene JSON: " + path + ": " + what);
}

void RejectUnknownKeys(const Json& j, std::initializer_list<std::string_view> allowed, const std::string& path) {
  for (const auto& item : j.items()) {
    if (std::find(allowed.begin(), allowed.end(), item.key()) == allowed.end()) {
      Fail(path, "unknown key \"" + item.key() + "\"");
    }
  }
}

const Json& Require(const Json& j, const char* key, const std::string& path) {
  const auto it = j.find(key);
  if (it == j.end()) Fail(path, std::string("missing \"") + key + "\"");
  return *it;
}

double AsFinite(const Json& v, const std::string& path) {
  if (!v.is_number()) Fail(path, "expected a number");
  const double x = v.get<double>();
  if (!std::isfinite(x)) Fail(path, "expected a finite number");
  return x;
}

template <int N>
Eigen::Matrix<double, N, 1> AsVector(const Json& v, const std::string& path) {
  if (!v.is_array() || v.size() != N) Fail(path, "expected an array of " + std::to_string(N) + " numbers");
  Eigen::Matrix<double, N, 1> out;
  for (int i = 0; i < N; ++i) out[i] = AsFinite(v[static_cast<std::size_t>(i)], path + "[" + std::to_string(i) + "]");
  return out;
}

std::string AsString(const Json& v, const std::string& path) {
  if (!v.is_string()) Fail(path, "expected a string");
  return v.get<std::string>();
}

Primitive ParsePrimitive(const Json& j, int object_id, const std::string& path) {
  if (!j.is_object()) Fail(path, "expected an object");
  RejectUnknownKeys(j, {"shape", "position", "orientation", "size"}, path);
  Primitive prim;
  prim.object_id = object_id;
  const std::string shape = AsString(Require(j, "shape", path), path + ".shape");
  if (shape == "box") {
    prim.shape = Shape::kBox;
  } else if (shape == "cylinder") {
    prim.shape = Shape::kCylinder;
  } else {
    Fail(path + ".shape", "expected \"box\" or \"cylinder\", got \"" + shape + "\"");
  }
  const Eigen::Vector3d position = AsVector<3>(Require(j, "position", path), path + ".position");
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  if (const auto it = j.find("orientation"); it != j.end()) {
    const Eigen::Vector4d xyzw = AsVector<4>(*it, path + ".orientation");
    if (std::abs(xyzw.norm() - 1.0) > 1e-3) {
      Fail(path + ".orientation",
           "quaternion [qx,qy,qz,qw] is not of unit length (norm " + std::to_string(xyzw.norm()) + ")");
    }
    q = Eigen::Quaterniond(xyzw[3], xyzw[0], xyzw[1], xyzw[2]).normalized();
  }
  prim.X_WorldPrim = Eigen::Isometry3d::Identity();
  prim.X_WorldPrim.linear() = q.toRotationMatrix();
  prim.X_WorldPrim.translation() = position;
  prim.size_m = AsVector<3>(Require(j, "size", path), path + ".size");
  if (prim.shape == Shape::kBox && !(prim.size_m.array() > 0.0).all()) {
    Fail(path + ".size", "box extents must be positive");
  }
  if (prim.shape == Shape::kCylinder && !(prim.size_m.x() > 0.0 && prim.size_m.z() > 0.0)) {
    Fail(path + ".size", "cylinder radius (size[0]) and height (size[2]) must be positive");
  }
  return prim;
}

void RequireKnownObject(const Scene& scene, int object_id, const char* function) {
  const bool known =
      std::any_of(scene.objects.begin(), scene.objects.end(), [&](const Object& o) { return o.id == object_id; }) ||
      std::any_of(scene.primitives.begin(), scene.primitives.end(),
                  [&](const Primitive& p) { return p.object_id == object_id; });
  if (!known) throw std::invalid_argument(std::string(function) + ": no object with id " + std::to_string(object_id));
}

const char* ShapeName(Shape shape) { return shape == Shape::kBox ? "box" : "cylinder"; }

}  // namespace

Scene SceneFromJson(const Json& j) {
  if (!j.is_object()) Fail("$", "expected an object with key \"objects\"");
  RejectUnknownKeys(j, {"objects"}, "$");
  const Json& objects = Require(j, "objects", "$");
  if (!objects.is_array()) Fail("objects", "expected an array");
  Scene scene;
  std::set<int> ids;
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const std::string path = "objects[" + std::to_string(i) + "]";
    const Json& o = objects[i];
    if (!o.is_object()) Fail(path, "expected an object");
    RejectUnknownKeys(o, {"id", "name", "kind", "primitives"}, path);
    const Json& id = Require(o, "id", path);
    if (!id.is_number_integer()) Fail(path + ".id", "expected an integer");
    const std::int64_t id_value = id.get<std::int64_t>();
    if (id_value < 1 || id_value > 2147483647) Fail(path + ".id", "must be in [1, 2147483647]");
    Object object;
    object.id = static_cast<int>(id_value);
    if (!ids.insert(object.id).second) Fail(path + ".id", "duplicate object id " + std::to_string(object.id));
    object.name = AsString(Require(o, "name", path), path + ".name");
    object.kind = AsString(Require(o, "kind", path), path + ".kind");
    if (object.kind != "static" && object.kind != "movable" && object.kind != "person") {
      Fail(path + ".kind", "expected \"static\", \"movable\" or \"person\", got \"" + object.kind + "\"");
    }
    const Json& primitives = Require(o, "primitives", path);
    if (!primitives.is_array()) Fail(path + ".primitives", "expected an array");
    for (std::size_t k = 0; k < primitives.size(); ++k) {
      scene.primitives.push_back(
          ParsePrimitive(primitives[k], object.id, path + ".primitives[" + std::to_string(k) + "]"));
    }
    scene.objects.push_back(std::move(object));
  }
  return scene;
}

Json SceneToJson(const Scene& scene) {
  for (std::size_t i = 0; i < scene.primitives.size(); ++i) {
    const int id = scene.primitives[i].object_id;
    if (std::none_of(scene.objects.begin(), scene.objects.end(), [&](const Object& o) { return o.id == id; })) {
      throw std::invalid_argument("SceneToJson: primitive " + std::to_string(i) + " belongs to object " +
                                  std::to_string(id) + ", which is not in scene.objects");
    }
  }
  Json objects = Json::array();
  for (const Object& object : scene.objects) {
    Json primitives = Json::array();
    for (const Primitive& p : scene.primitives) {
      if (p.object_id != object.id) continue;
      const Eigen::Quaterniond q(p.X_WorldPrim.linear());
      const Eigen::Vector3d t = p.X_WorldPrim.translation();
      primitives.push_back({{"shape", ShapeName(p.shape)},
                            {"position", {t.x(), t.y(), t.z()}},
                            {"orientation", {q.x(), q.y(), q.z(), q.w()}},
                            {"size", {p.size_m.x(), p.size_m.y(), p.size_m.z()}}});
    }
    objects.push_back({{"id", object.id}, {"name", object.name}, {"kind", object.kind}, {"primitives", primitives}});
  }
  return {{"objects", objects}};
}

void MoveObject(Scene& scene, int object_id, const Eigen::Isometry3d& X_delta_world) {
  RequireKnownObject(scene, object_id, "MoveObject");
  for (Primitive& p : scene.primitives) {
    if (p.object_id == object_id) p.X_WorldPrim = X_delta_world * p.X_WorldPrim;
  }
}

void RemoveObject(Scene& scene, int object_id) {
  RequireKnownObject(scene, object_id, "RemoveObject");
  std::erase_if(scene.primitives, [&](const Primitive& p) { return p.object_id == object_id; });
  std::erase_if(scene.objects, [&](const Object& o) { return o.id == object_id; });
}

}  // namespace anchordb::sim
