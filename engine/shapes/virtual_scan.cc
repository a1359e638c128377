#include "engine/shapes/virtual_scan.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "schema/error.h"

namespace anchordb::engine {
namespace {

[[noreturn]] void BadMesh(std::size_t line, const std::string& why) {
  throw Error(ErrorCode::kUnprocessable, "mesh line " + std::to_string(line) + ": " + why, "mesh");
}

// "12", "12/3", "12/3/4", "12//4" -> 12; negative indices count from the end (OBJ).
long FaceIndex(const std::string& token, std::size_t line) {
  const std::string head = token.substr(0, token.find('/'));
  std::size_t used = 0;
  long v = 0;
  try {
    v = std::stol(head, &used);
  } catch (const std::exception&) {
    BadMesh(line, "face index '" + token.substr(0, 20) + "' is not a number");
  }
  if (used != head.size()) BadMesh(line, "face index '" + token.substr(0, 20) + "' is not a number");
  return v;
}

}  // namespace

TriangleMesh ParseObj(std::string_view text) {
  TriangleMesh mesh;
  std::istringstream in{std::string(text)};
  std::string raw;
  std::size_t line = 0;
  while (std::getline(in, raw)) {
    ++line;
    std::istringstream ls(raw);
    std::string tag;
    if (!(ls >> tag)) continue;
    if (tag == "v") {
      double x, y, z;
      if (!(ls >> x >> y >> z)) BadMesh(line, "a vertex needs three numbers");
      const Eigen::Vector3f v(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
      if (!v.allFinite()) BadMesh(line, "a vertex is not finite");
      mesh.vertices_m.push_back(v);
    } else if (tag == "f") {
      std::vector<int> ids;
      std::string token;
      while (ls >> token) {
        const long k = FaceIndex(token, line);
        const long n = static_cast<long>(mesh.vertices_m.size());
        const long id = k > 0 ? k - 1 : n + k;
        if (k == 0 || id < 0 || id >= n) BadMesh(line, "face index " + std::to_string(k) + " is out of range");
        ids.push_back(static_cast<int>(id));
      }
      if (ids.size() < 3) BadMesh(line, "a face needs at least 3 vertices");
      for (std::size_t i = 1; i + 1 < ids.size(); ++i) mesh.triangles.emplace_back(ids[0], ids[i], ids[i + 1]);
    }
  }
  if (mesh.triangles.empty()) throw Error(ErrorCode::kUnprocessable, "the mesh has no face", "mesh");
  return mesh;
}

std::vector<double> RenderMeshDepth(const TriangleMesh& mesh, const Eigen::Isometry3d& X_WorldMesh,
                                    const ScanCamera& cam, const Eigen::Isometry3d& X_WorldCamera) {
  const int w = cam.width, h = cam.height;
  std::vector<double> depth(static_cast<std::size_t>(w) * h, 0.0);
  const Eigen::Isometry3d X_CameraMesh = X_WorldCamera.inverse() * X_WorldMesh;
  std::vector<Eigen::Vector3d> cv(mesh.vertices_m.size());
  for (std::size_t i = 0; i < cv.size(); ++i) cv[i] = X_CameraMesh * mesh.vertices_m[i].cast<double>();
  constexpr double kNear = 0.05;
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d& a = cv[t[0]];
    const Eigen::Vector3d& b = cv[t[1]];
    const Eigen::Vector3d& c = cv[t[2]];
    if (a.z() < kNear || b.z() < kNear || c.z() < kNear) continue;  // the camera stands outside the mesh
    // Screen positions; 1/z is affine in screen space, so depth is interpolated as 1 / (barycentric of 1/z).
    const auto project = [&](const Eigen::Vector3d& p) {
      return Eigen::Vector2d(cam.fx * p.x() / p.z() + cam.cx, cam.fy * p.y() / p.z() + cam.cy);
    };
    const Eigen::Vector2d pa = project(a), pb = project(b), pc = project(c);
    const double area = (pb - pa).x() * (pc - pa).y() - (pb - pa).y() * (pc - pa).x();
    if (std::abs(area) < 1e-12) continue;
    const int u0 = std::max(0, static_cast<int>(std::floor(std::min({pa.x(), pb.x(), pc.x()}))));
    const int u1 = std::min(w - 1, static_cast<int>(std::ceil(std::max({pa.x(), pb.x(), pc.x()}))));
    const int v0 = std::max(0, static_cast<int>(std::floor(std::min({pa.y(), pb.y(), pc.y()}))));
    const int v1 = std::min(h - 1, static_cast<int>(std::ceil(std::max({pa.y(), pb.y(), pc.y()}))));
    for (int v = v0; v <= v1; ++v) {
      for (int u = u0; u <= u1; ++u) {
        const Eigen::Vector2d q(u, v);
        const double l1 = ((pc - pb).x() * (q - pb).y() - (pc - pb).y() * (q - pb).x()) / area;
        const double l2 = ((pa - pc).x() * (q - pc).y() - (pa - pc).y() * (q - pc).x()) / area;
        const double l3 = 1.0 - l1 - l2;
        if (l1 < 0 || l2 < 0 || l3 < 0) continue;
        const double z = 1.0 / (l1 / a.z() + l2 / b.z() + l3 / c.z());
        if (z > cam.max_range_m) continue;
        double& d = depth[static_cast<std::size_t>(v) * w + u];
        if (d == 0 || z < d) d = z;
      }
    }
  }
  return depth;
}

std::vector<Eigen::Vector3f> DepthToWorldPoints(const std::vector<double>& depth_m, const ScanCamera& cam,
                                                const Eigen::Isometry3d& X_WorldCamera) {
  std::vector<Eigen::Vector3f> out;
  for (int v = 0; v < cam.height; ++v) {
    for (int u = 0; u < cam.width; ++u) {
      const double z = depth_m[static_cast<std::size_t>(v) * cam.width + u];
      if (!(z > 0)) continue;
      const Eigen::Vector3d p((u - cam.cx) / cam.fx * z, (v - cam.cy) / cam.fy * z, z);
      out.push_back((X_WorldCamera * p).cast<float>());
    }
  }
  return out;
}

std::vector<Eigen::Isometry3d> ScanViewpoints(const TriangleMesh& mesh, int views, double azimuth0_rad,
                                              double elevation_rad, double distance_factor) {
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max()), hi = -lo;
  for (const auto& v : mesh.vertices_m) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const Eigen::Vector3d centre = (0.5f * (lo + hi)).cast<double>();
  const double distance = std::max(1.0, distance_factor * static_cast<double>((hi - lo).norm()));
  std::vector<Eigen::Isometry3d> out;
  for (int i = 0; i < views; ++i) {
    const double azimuth = azimuth0_rad + 2.0 * 3.14159265358979323846 * i / views;
    const Eigen::Vector3d eye = centre + distance * Eigen::Vector3d(std::cos(elevation_rad) * std::cos(azimuth),
                                                                    std::cos(elevation_rad) * std::sin(azimuth),
                                                                    std::sin(elevation_rad));
    // Optical frame looking at the centre: z forward, x right (horizontal), y down.
    const Eigen::Vector3d z = (centre - eye).normalized();
    Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ());
    if (x.norm() < 1e-9) x = Eigen::Vector3d::UnitX();
    x.normalize();
    const Eigen::Vector3d y = z.cross(x);
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear().col(0) = x;
    pose.linear().col(1) = y;
    pose.linear().col(2) = z;
    pose.translation() = eye;
    out.push_back(pose);
  }
  return out;
}

std::vector<std::vector<Eigen::Vector3f>> VirtualScans(const TriangleMesh& mesh, int views, const ScanCamera& camera) {
  std::vector<std::vector<Eigen::Vector3f>> out;
  for (const auto& pose : ScanViewpoints(mesh, views, 0.0, 0.5)) {
    out.push_back(DepthToWorldPoints(RenderMeshDepth(mesh, Eigen::Isometry3d::Identity(), camera, pose), camera, pose));
  }
  return out;
}

}  // namespace anchordb::engine
