#include "tests/eval/mesh_furniture.h"

#include <cmath>
#include <fstream>
#include <numbers>
#include <random>
#include <sstream>

#include "sim/sensor_artefacts.h"

namespace anchordb::eval {

std::optional<engine::TriangleMesh> ReadObjFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  std::stringstream text;
  text << in.rdbuf();
  return engine::ParseObj(text.str());
}

MeshBounds Bounds(const engine::TriangleMesh& mesh) {
  MeshBounds b{Eigen::Vector3f::Constant(1e9f), Eigen::Vector3f::Constant(-1e9f)};
  for (const auto& v : mesh.vertices_m) b.lo = b.lo.cwiseMin(v), b.hi = b.hi.cwiseMax(v);
  return b;
}

MeshFit FitMesh(const MeshBounds& b, int quarter_turns, const Eigen::Vector2d& centre_m, double yaw_rad,
                double piece_depth_m, double wall_side, double z0_m) {
  const Eigen::Vector3f size = b.hi - b.lo;
  const bool odd = quarter_turns % 2 != 0;
  const double yaw = yaw_rad + quarter_turns * (std::numbers::pi / 2);
  const Eigen::Vector2d own_y = Eigen::Rotation2Dd(yaw_rad) * Eigen::Vector2d(0, 1);
  const double depth = odd ? size.x() : size.y();  // the mesh's extent along the piece's own y
  MeshFit fit;
  fit.centre_m = centre_m + own_y * 0.5 * (piece_depth_m - depth) * wall_side;
  fit.extent_m = odd ? Eigen::Vector2d(size.y(), size.x()) : Eigen::Vector2d(size.x(), size.y());
  fit.height_m = size.z();
  fit.X_WorldMesh.translation() = Eigen::Vector3d(fit.centre_m.x(), fit.centre_m.y(), z0_m - b.lo.z());
  fit.X_WorldMesh.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  fit.X_WorldMesh = fit.X_WorldMesh * Eigen::Translation3d(-0.5 * (b.lo + b.hi).x(), -0.5 * (b.lo + b.hi).y(), 0.0);
  return fit;
}

engine::ScanCamera ScanCameraOf(const PinholeIntrinsics& K) {
  engine::ScanCamera cam;
  cam.width = K.width, cam.height = K.height, cam.fx = K.fx, cam.fy = K.fy, cam.cx = K.cx, cam.cy = K.cy;
  return cam;
}

void ZBufferMeshes(const std::vector<PlacedMesh>& meshes, const engine::ScanCamera& camera,
                   const Eigen::Isometry3d& X_WorldCamera, double min_z_m, std::vector<double>& nearest,
                   const std::function<void(std::size_t, double)>& nearer) {
  for (const PlacedMesh& m : meshes) {
    const std::vector<double> d = engine::RenderMeshDepth(*m.mesh, m.X_WorldMesh, camera, X_WorldCamera);
    for (std::size_t px = 0; px < d.size(); ++px) {
      if (!(d[px] > min_z_m)) continue;
      if (nearest[px] > 0 && d[px] >= nearest[px]) continue;
      nearer(px, d[px]);
      nearest[px] = d[px];
    }
  }
}

namespace {

// Whether the surface at pixel (u, v) of the ideal depth image is seen within max_incidence_rad of its normal, the
// normal from the nearest-in-depth horizontal and vertical neighbours; true where no neighbour lies within 5 cm.
bool SeenWithinIncidence(const std::vector<double>& z, const engine::ScanCamera& cam, int u, int v,
                         double cos_max_incidence) {
  const auto at = [&](int uu, int vv) { return z[static_cast<std::size_t>(vv) * cam.width + uu]; };
  const auto point = [&](int uu, int vv) {
    const double d = at(uu, vv);
    return Eigen::Vector3d((uu - cam.cx) / cam.fx * d, (vv - cam.cy) / cam.fy * d, d);
  };
  const double z0 = at(u, v);
  const auto neighbour = [&](int du, int dv, Eigen::Vector3d& out) {
    double best = 0.05;
    bool found = false;
    for (int s : {1, -1}) {
      const int uu = u + s * du, vv = v + s * dv;
      if (uu < 0 || vv < 0 || uu >= cam.width || vv >= cam.height || !(at(uu, vv) > 0)) continue;
      const double jump = std::abs(at(uu, vv) - z0);
      if (jump >= best) continue;
      best = jump;
      out = (point(uu, vv) - point(u, v)) * s;
      found = true;
    }
    return found;
  };
  Eigen::Vector3d du, dv;
  if (!neighbour(1, 0, du) || !neighbour(0, 1, dv)) return true;
  const Eigen::Vector3d n = du.cross(dv);
  const Eigen::Vector3d ray = point(u, v);
  return std::abs(n.dot(ray)) >= cos_max_incidence * n.norm() * ray.norm();
}

}  // namespace

std::vector<std::uint16_t> ScanWithMeshes(const sim::Scene& scene, const std::vector<PlacedMesh>& meshes,
                                          const PinholeIntrinsics& K, const Eigen::Isometry3d& X_WorldCamera,
                                          const sim::SensorModel& sensor, std::uint64_t seed) {
  sim::SensorModel exact = sensor;
  exact.noise = false;  // depth only where range, incidence and shadow let the sensor measure the boxes
  const sim::Frame f = sim::Render(scene, K, X_WorldCamera, exact, seed);
  const std::size_t n = f.depth_mm.size();
  std::vector<double> nearest(n, 0.0), ideal(n, 0.0);
  for (std::size_t px = 0; px < n; ++px) {
    nearest[px] = f.true_depth_m[px];  // a box occludes a mesh behind it also where it is not measured
    if (f.depth_mm[px] > 0) ideal[px] = f.true_depth_m[px];
  }
  const engine::ScanCamera cam = ScanCameraOf(K);
  std::vector<char> mesh_pixel(n, 0);
  ZBufferMeshes(meshes, cam, X_WorldCamera, 0.0, nearest, [&](std::size_t px, double) { mesh_pixel[px] = 1; });
  const double cos_max_incidence = std::cos(sensor.max_incidence_rad);
  for (int v = 0; v < cam.height; ++v) {
    for (int u = 0; u < cam.width; ++u) {
      const std::size_t px = static_cast<std::size_t>(v) * cam.width + u;
      if (!mesh_pixel[px]) continue;
      const double z = nearest[px];
      const bool measured = z >= sensor.min_range_m && z <= sensor.max_range_m &&
                            SeenWithinIncidence(nearest, cam, u, v, cos_max_incidence);
      ideal[px] = measured ? z : 0.0;
    }
  }
  std::vector<double> white(n, 0.0);
  std::mt19937_64 rng(seed ^ 0x9e3779b97f4a7c15ULL);
  std::normal_distribution<double> normal;
  for (double& w : white) w = normal(rng);
  std::vector<std::uint16_t> depth_mm;
  sim::detail::MeasureDepth(sensor, cam.width, cam.height, seed, ideal, white, depth_mm);
  return depth_mm;
}

}  // namespace anchordb::eval
