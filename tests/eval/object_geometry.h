#pragma once
// Geometry of rendered objects for the merge evaluation: surface samples, footprints, visibility from a camera, and
// the search for a free spot on a surface that is hidden from one viewpoint and shown to another.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <stdexcept>
#include <vector>

#include "engine/scene/projection.h"
#include "sim/renderer.h"
#include "tests/eval/merge_cases.h"  // MergeCase, MergeCaseName (NoSpot)

namespace anchordb::eval::geometry {

using Eigen::Isometry3d;
using Eigen::Vector2d;
using Eigen::Vector3d;

inline Isometry3d Translation(const Vector3d& t) {
  Isometry3d X = Isometry3d::Identity();
  X.translation() = t;
  return X;
}

// ---- geometry of objects ---------------------------------------------------------------------------------------

struct SurfaceSample {
  Vector3d p, n;  // world point and outward normal
};

// Points on the surfaces of all primitives of an object (box faces on a 6 x 6 grid; cylinder sides and caps).
inline std::vector<SurfaceSample> ObjectSamples(const sim::Scene& scene, int id) {
  std::vector<SurfaceSample> out;
  for (const auto& prim : scene.primitives) {
    if (prim.object_id != id) continue;
    const auto add = [&](const Vector3d& p_local, const Vector3d& n_local) {
      out.push_back({prim.X_WorldPrim * p_local, prim.X_WorldPrim.linear() * n_local});
    };
    const Vector3d& s = prim.size_m;
    if (prim.shape == sim::Shape::kBox) {
      constexpr int kGrid = 6;
      for (int a = 0; a < 3; ++a) {
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        for (const double sign : {-1.0, 1.0}) {
          for (int i = 0; i < kGrid; ++i) {
            for (int j = 0; j < kGrid; ++j) {
              Vector3d p = Vector3d::Zero(), n = Vector3d::Zero();
              p[a] = sign * 0.5 * s[a];
              p[b] = (-0.5 + (i + 0.5) / kGrid) * s[b];
              p[c] = (-0.5 + (j + 0.5) / kGrid) * s[c];
              n[a] = sign;
              add(p, n);
            }
          }
        }
      }
    } else {
      const double r = s.x(), h = s.z();
      for (int k = 0; k < 24; ++k) {
        const double phi = k * 2.0 * std::numbers::pi / 24;
        const Vector3d radial(std::cos(phi), std::sin(phi), 0.0);
        for (int j = 0; j < 6; ++j) add(radial * r + Vector3d(0, 0, (-0.5 + (j + 0.5) / 6) * h), radial);
        for (const double f : {0.35, 0.7}) {
          add(radial * r * f + Vector3d(0, 0, 0.5 * h), Vector3d::UnitZ());
          add(radial * r * f - Vector3d(0, 0, 0.5 * h), -Vector3d::UnitZ());
        }
      }
      add(Vector3d(0, 0, 0.5 * h), Vector3d::UnitZ());
      add(Vector3d(0, 0, -0.5 * h), -Vector3d::UnitZ());
    }
  }
  if (out.empty()) throw std::invalid_argument("object not in scene");
  return out;
}

// Horizontal footprint of an upright object, grown by `margin_m`, as world xy points.
inline std::vector<Vector2d> Footprint(const sim::Scene& scene, int id, double margin_m) {
  std::vector<Vector2d> out;
  for (const auto& prim : scene.primitives) {
    if (prim.object_id != id) continue;
    const Vector3d& s = prim.size_m;
    if (prim.shape == sim::Shape::kBox) {
      constexpr int kGrid = 7;
      for (int i = 0; i < kGrid; ++i) {
        for (int j = 0; j < kGrid; ++j) {
          const Vector3d p((-0.5 + i / (kGrid - 1.0)) * (s.x() + 2 * margin_m),
                           (-0.5 + j / (kGrid - 1.0)) * (s.y() + 2 * margin_m), 0.0);
          out.push_back((prim.X_WorldPrim * p).head<2>());
        }
      }
    } else {
      out.push_back(prim.X_WorldPrim.translation().head<2>());
      for (const double f : {0.5, 1.0}) {
        for (int k = 0; k < 16; ++k) {
          const double phi = k * 2.0 * std::numbers::pi / 16;
          const Vector3d p = Vector3d(std::cos(phi), std::sin(phi), 0.0) * f * (s.x() + margin_m);
          out.push_back((prim.X_WorldPrim * p).head<2>());
        }
      }
    }
  }
  return out;
}

inline Vector3d Centre(const sim::Scene& scene, int id) {
  for (const auto& p : scene.primitives) if (p.object_id == id) return p.X_WorldPrim.translation();
  throw std::invalid_argument("object not in scene");
}

// Top of an upright box-shaped object (its first primitive).
inline Vector3d TopCentre(const sim::Scene& scene, int id) {
  for (const auto& p : scene.primitives) {
    if (p.object_id != id) continue;
    return p.X_WorldPrim.translation() + Vector3d(0, 0, 0.5 * p.size_m.z());
  }
  throw std::invalid_argument("object not in scene");
}

inline double Height(const sim::Scene& scene, int id) {
  for (const auto& p : scene.primitives) if (p.object_id == id) return p.size_m.z();
  throw std::invalid_argument("object not in scene");
}

inline sim::SensorModel Noiseless() {
  sim::SensorModel s;
  s.noise = false;
  s.shadow = false;
  s.min_range_m = 0.0;
  s.max_range_m = 100.0;
  return s;
}

// A top-down view of the supporting surface (camera 0.3 m above it, below any board above it): tells whether a
// footprint rests entirely on the bare surface (a static object's top at the surface's height, nothing on it).
class SurfaceProbe {
 public:
  SurfaceProbe(const sim::Scene& scene, const Vector3d& surface_m) : surface_z_(surface_m.z()) {
    const Vector3d eye = surface_m + Vector3d(0, 0, kHeight);
    X_CW_ = sim::LookAt(eye, surface_m).inverse();
    K_.width = K_.height = 2 * kHalf + 1;
    K_.fx = K_.fy = kHalf * kHeight / kReach;
    K_.cx = K_.cy = kHalf;
    frame_ = sim::Render(scene, K_, X_CW_.inverse(), Noiseless(), 0);
    for (const auto& o : scene.objects) static_[o.id] = o.kind == "static";
  }
  bool Free(const Vector2d& xy) const {
    const Vector3d p = X_CW_ * Vector3d(xy.x(), xy.y(), surface_z_);
    const double u = K_.fx * p.x() / p.z() + K_.cx, v = K_.fy * p.y() / p.z() + K_.cy;
    if (u < 0 || v < 0 || u >= K_.width || v >= K_.height) return false;
    const std::size_t i = static_cast<std::size_t>(v) * K_.width + static_cast<std::size_t>(u);
    const auto it = static_.find(frame_.object_id[i]);
    if (it == static_.end() || !it->second) return false;
    return std::abs(frame_.true_depth_m[i] - kHeight) < 0.004;
  }

 private:
  static constexpr int kHalf = 120;
  static constexpr double kHeight = 0.3, kReach = 0.6;  // sees +-0.6 m around the surface point
  double surface_z_;
  Isometry3d X_CW_;
  PinholeIntrinsics K_;
  sim::Frame frame_;
  std::map<int, bool> static_;
};

// The noiseless depth of a scene from one camera, to test where an object placed into it would be seen.
struct View {
  Isometry3d X_WC;
  Isometry3d X_CW;
  PinholeIntrinsics K;
  std::vector<float> depth;
  double max_range_m = 100.0;
};

inline View MakeView(const sim::Scene& scene_without, const Isometry3d& X_WC, const PinholeIntrinsics& K,
              double max_range_m = 100.0) {
  View v{X_WC, X_WC.inverse(), K, sim::Render(scene_without, K, X_WC, Noiseless(), 0).true_depth_m, max_range_m};
  return v;
}

struct Visibility {
  int facing = 0, visible = 0, hidden = 0;
  double Fraction() const { return facing ? static_cast<double>(visible) / facing : 0.0; }
  // Every surface point that faces the camera is inside the image and clearly (2 cm) behind something.
  bool FullyOccluded() const { return facing > 0 && hidden == facing; }
};

inline Visibility See(const std::vector<SurfaceSample>& samples, const Vector3d& delta, const View& view) {
  Visibility vis;
  const Vector3d eye = view.X_WC.translation();
  for (const auto& s : samples) {
    const Vector3d p = s.p + delta;
    if (s.n.dot(eye - p) <= 1e-9) continue;
    ++vis.facing;
    const Vector3d c = view.X_CW * p;
    if (c.z() <= 0.05) continue;
    const double u = view.K.fx * c.x() / c.z() + view.K.cx, v = view.K.fy * c.y() / c.z() + view.K.cy;
    if (u < 0 || v < 0 || u >= view.K.width || v >= view.K.height) continue;
    const float d = view.depth[static_cast<std::size_t>(v) * view.K.width + static_cast<std::size_t>(u)];
    if ((d == 0.0f || c.z() < d + 0.01) && c.z() <= view.max_range_m) {
      ++vis.visible;
    } else if (d > 0.0f && c.z() > d + 0.02) {
      ++vis.hidden;
    }
  }
  return vis;
}

// Whether any sample of the object, moved by `delta`, projects onto a set pixel of `mask` (an image of the view).
inline bool Covers(const std::vector<SurfaceSample>& samples, const Vector3d& delta, const View& view,
                   const std::vector<std::uint8_t>& mask) {
  for (const auto& s : samples) {
    const Vector3d c = view.X_CW * (s.p + delta);
    if (c.z() <= 0.05) continue;
    const double u = view.K.fx * c.x() / c.z() + view.K.cx, v = view.K.fy * c.y() / c.z() + view.K.cy;
    if (u < 0 || v < 0 || u >= view.K.width || v >= view.K.height) continue;
    if (mask[static_cast<std::size_t>(v) * view.K.width + static_cast<std::size_t>(u)]) return true;
  }
  return false;
}

// The pixels of a camera that the objects `ids` of `scene` cover, grown by `grow_px` in every direction.
inline std::vector<std::uint8_t> Silhouette(const sim::Scene& scene, const std::vector<int>& ids,
                                            const Isometry3d& X_WC, const PinholeIntrinsics& K, int grow_px) {
  const sim::Frame f = sim::Render(scene, K, X_WC, Noiseless(), 0);
  std::vector<std::uint8_t> mask(f.object_id.size(), 0);
  for (int v = 0; v < K.height; ++v) {
    for (int u = 0; u < K.width; ++u) {
      const int id = f.object_id[static_cast<std::size_t>(v) * K.width + u];
      if (std::find(ids.begin(), ids.end(), id) == ids.end()) continue;
      for (int dv = -grow_px; dv <= grow_px; ++dv) {
        for (int du = -grow_px; du <= grow_px; ++du) {
          const int uu = u + du, vv = v + dv;
          if (uu >= 0 && vv >= 0 && uu < K.width && vv < K.height) mask[static_cast<std::size_t>(vv) * K.width + uu] = 1;
        }
      }
    }
  }
  return mask;
}

// Where to put an object on the supporting surface.
struct SpotQuery {
  struct Camera {
    const View* view;
    bool hidden;          // true: fully occluded there; false: at least `min_visible` of its facing surface seen
    double min_visible = 0.9;
    // If set: pixels of this camera the object must not cover at its new place (see Silhouette).
    const std::vector<std::uint8_t>* avoid = nullptr;
  };
  std::vector<Camera> cameras;
  double min_move_m = 0.0, max_move_m = 0.45, preferred_move_m = 0.2;
  double margin_m = 0.015;  // free space kept around the footprint
  bool prefer_visible = false;  // choose the place seen best by the `hidden == false` cameras, then by distance
  std::optional<Vector2d> target;  // if set: the place nearest to this point (instead of preferred_move_m)
};

// Searches a 1 cm grid around the surface point for the object's centre: the grown footprint must lie on the bare
// surface of `probe_scene` (which still contains the object at its old place when it is moved, so the new place
// never overlaps the old one), and every camera's requirement must hold. Returns the translation to apply.
inline std::optional<Vector3d> FindSpot(const sim::Scene& with_object, int id, const sim::Scene& probe_scene,
                                 const Vector3d& surface_m, const SpotQuery& q) {
  const SurfaceProbe probe(probe_scene, surface_m);
  const std::vector<SurfaceSample> samples = ObjectSamples(with_object, id);
  const std::vector<Vector2d> footprint = Footprint(with_object, id, q.margin_m);
  const Vector3d origin = Centre(with_object, id);
  double best_cost = std::numeric_limits<double>::infinity();
  std::optional<Vector3d> best;
  for (int i = -60; i <= 60; ++i) {
    for (int j = -60; j <= 60; ++j) {
      const Vector3d delta(surface_m.x() + 0.01 * i - origin.x(), surface_m.y() + 0.01 * j - origin.y(), 0.0);
      const double move = delta.norm();
      if (move < q.min_move_m || move > q.max_move_m) continue;
      bool free = true;
      for (const auto& f : footprint) free = free && probe.Free(f + delta.head<2>());
      if (!free) continue;
      bool ok = true;
      double seen = 1.0;
      for (const auto& cam : q.cameras) {
        if (cam.avoid && Covers(samples, delta, *cam.view, *cam.avoid)) {
          ok = false;
          break;
        }
        const Visibility vis = See(samples, delta, *cam.view);
        if (cam.hidden) {
          ok = ok && vis.FullyOccluded();
        } else {
          ok = ok && vis.Fraction() >= cam.min_visible;
          seen = std::min(seen, vis.Fraction());
        }
        if (!ok) break;
      }
      if (!ok) continue;
      const double distance = q.target ? (origin.head<2>() + delta.head<2>() - *q.target).norm()
                                       : std::abs(move - q.preferred_move_m);
      const double cost = (q.prefer_visible ? -seen : 0.0) + 0.01 * distance;
      if (cost < best_cost) best_cost = cost, best = delta;
    }
  }
  return best;
}

inline std::string Fmt(const Vector3d& d) {
  std::ostringstream s;
  s.precision(2);
  s << std::fixed << "(" << d.x() << ", " << d.y() << ")";
  return s.str();
}

[[noreturn]] inline void NoSpot(MergeCase c, sim::Setting s, const char* what) {
  throw std::runtime_error(std::string("merge case ") + MergeCaseName(c) + " in " + sim::SettingName(s) +
                           ": no place found for " + what);
}

inline sim::Scene Without(sim::Scene scene, int id) {
  const bool present =
      std::any_of(scene.objects.begin(), scene.objects.end(), [&](const sim::Object& o) { return o.id == id; });
  if (present) sim::RemoveObject(scene, id);
  return scene;
}

inline sim::Scene Moved(sim::Scene scene, int id, const Vector3d& delta) {
  sim::MoveObject(scene, id, Translation(delta));
  return scene;
}

// A spot visible from both viewpoints (at least 90 % of the object's facing surface seen from each) for an object
// that moves 12-35 cm (preferably 20 cm) from where it stands in `scene`: far enough that its new volume does not
// overlap its old one, and -- in A's image -- off the places where the objects `moving` (default: this one) stood
// when A began to observe (`a_before`, default `scene`). Otherwise A's model itself goes wrong, whatever a merge
// does later (an A1-like effect in the image): where the object's new place lies behind an old place, Algorithm 1 at
// A takes it for background uncovered by the move; where it lies in front, A's background keeps the surface of the
// old place, which the move has taken away. Where the surface is too crowded for that (the shelf board with some
// seeds), 80 % and up to 45 cm, then also only 0.5 cm instead of 1.5 cm of free space around it, then up to 60 cm;
// only then also places that overlap in A's image (the case's description says so).
inline std::optional<Vector3d> VisibleMove(const sim::Scene& scene, int id, const Vector3d& surface, const Isometry3d& XA,
                                    const Isometry3d& XB, const PinholeIntrinsics& K,
                                    const sim::Scene* a_before = nullptr, std::vector<int> moving = {},
                                    bool* overlaps_in_a = nullptr) {
  const sim::Scene without = Without(scene, id);
  const View a = MakeView(without, XA, K), b = MakeView(without, XB, K);
  if (moving.empty()) moving = {id};
  const std::vector<std::uint8_t> old_places = Silhouette(a_before ? *a_before : scene, moving, XA, K, 3);
  struct Try {
    double visible, max_move, margin;
  };
  for (const bool avoid : {true, false}) {
    for (const Try t : {Try{0.9, 0.35, 0.015}, Try{0.8, 0.45, 0.015}, Try{0.8, 0.45, 0.005}, Try{0.8, 0.6, 0.005}}) {
      SpotQuery q;
      q.cameras = {{&a, false, t.visible, avoid ? &old_places : nullptr}, {&b, false, t.visible}};
      q.min_move_m = 0.12;
      q.max_move_m = t.max_move;
      q.margin_m = t.margin;
      q.preferred_move_m = 0.2;
      if (auto d = FindSpot(scene, id, scene, surface, q)) {
        if (overlaps_in_a) *overlaps_in_a = !avoid;
        return d;
      }
    }
  }
  return std::nullopt;
}

// A spot occluded from `X_hidden` (every point of it behind something) and seen as well as possible from the
// `X_seen` cameras (at least 60 % of its facing surface), anywhere on the surface; the object is absent from
// `probe_scene` when it is added, present at its old place when it is moved.
inline std::optional<Vector3d> HiddenSpot(const sim::Scene& with_object, int id, const sim::Scene& probe_scene,
                                   const Vector3d& surface, const Isometry3d& X_hidden,
                                   const std::vector<Isometry3d>& X_seen, const PinholeIntrinsics& K,
                                   double min_seen = 0.6) {
  const sim::Scene without = Without(probe_scene, id);
  const View h = MakeView(without, X_hidden, K);
  std::vector<View> seen;
  for (const auto& X : X_seen) seen.push_back(MakeView(without, X, K));
  SpotQuery q;
  q.cameras = {{&h, true}};
  for (const auto& v : seen) q.cameras.push_back({&v, false, min_seen});
  q.min_move_m = 0.0;
  q.max_move_m = 0.85;
  q.preferred_move_m = 0.0;
  q.prefer_visible = true;
  return FindSpot(with_object, id, probe_scene, surface, q);
}

// Sets the box up as an occluder for `X_hide`: turned so that its wide side (15 cm) faces that camera and put on
// the bare place nearest to 15 cm in front of the surface point (towards the camera), so that there is bare
// surface behind it, in its shadow, that another viewpoint 45 cm away can see into.
inline std::optional<sim::Scene> WithOccluder(const sim::Scene& scene, int box, const Vector3d& surface,
                                       const Isometry3d& X_hide) {
  Vector2d towards = (surface - X_hide.translation()).head<2>();
  towards.normalize();
  const Eigen::Matrix3d R = [&] {
    for (const auto& p : scene.primitives) if (p.object_id == box) return p.X_WorldPrim.linear();
    throw std::invalid_argument("object not in scene");
  }();
  // The box's local x (its 10 cm side) along the line of sight.
  const double yaw = std::atan2(towards.y(), towards.x()) - std::atan2(R(1, 0), R(0, 0));
  const Vector3d c = Centre(scene, box);
  sim::Scene turned = scene;
  sim::MoveObject(turned, box, Translation(c) * Eigen::AngleAxisd(yaw, Vector3d::UnitZ()) * Translation(-c));
  SpotQuery q;
  q.max_move_m = 1.0;
  q.target = surface.head<2>() - 0.15 * towards;
  const auto d = FindSpot(turned, box, Without(scene, box), surface, q);
  if (!d) return std::nullopt;
  return Moved(turned, box, *d);
}

}  // namespace anchordb::eval::geometry
