// anchordb-render: renders a synthetic depth image and an object-id picture from a JSON scene or a built-in
// evaluation setting. See `anchordb-render --help`.
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <opencv2/core.hpp>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/apartment.h"
#include "sim/png_writer.h"
#include "sim/renderer.h"

namespace {

using anchordb::sim::Setting;

constexpr const char* kUsage =
    "usage: anchordb-render (--scene scene.json --camera x,y,z,tx,ty,tz | --setting TA|SE|CA|DO|KI1|KI2|SO\n"
    "                        [--viewpoint A|B]) [--seed N] [--no-noise] [--dump-scene scene.json] --out prefix\n"
    "Writes prefix_depth.png (16-bit, millimetres, 0 = no measurement) and prefix_ids.png (8-bit colour, one\n"
    "colour per object id, shaded by surface orientation, black = nothing hit). --camera gives the eye and the\n"
    "target point in the world frame [m] (Kinect intrinsics 640x480, f = 525). --seed (default 1) seeds the\n"
    "sensor noise and, with --setting, the small variations of the setting's objects. --dump-scene writes the\n"
    "rendered scene as JSON.\n";

struct Options {
  std::optional<std::string> scene_path;
  std::optional<std::string> camera;
  std::optional<std::string> setting;
  std::string viewpoint = "A";
  std::uint64_t seed = 1;
  bool noise = true;
  std::optional<std::string> dump_scene_path;
  std::string out_prefix;
};

class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

Options ParseArgs(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw UsageError(arg + " needs a value");
      return argv[++i];
    };
    if (arg == "--help" || arg == "-h") {
      std::cout << kUsage;
      std::exit(0);
    } else if (arg == "--scene") {
      o.scene_path = value();
    } else if (arg == "--camera") {
      o.camera = value();
    } else if (arg == "--setting") {
      o.setting = value();
    } else if (arg == "--viewpoint") {
      o.viewpoint = value();
    } else if (arg == "--seed") {
      const std::string text = value();
      std::size_t used = 0;
      try {
        o.seed = std::stoull(text, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != text.size() || text.empty() || text[0] == '-') throw UsageError("--seed expects an integer >= 0");
    } else if (arg == "--no-noise") {
      o.noise = false;
    } else if (arg == "--dump-scene") {
      o.dump_scene_path = value();
    } else if (arg == "--out") {
      o.out_prefix = value();
    } else {
      throw UsageError("unknown argument " + arg);
    }
  }
  if (o.out_prefix.empty()) throw UsageError("--out is required");
  if (o.setting.has_value() == (o.scene_path.has_value() || o.camera.has_value())) {
    throw UsageError("give either --setting or --scene with --camera");
  }
  if (o.scene_path.has_value() != o.camera.has_value()) throw UsageError("--scene and --camera go together");
  if (o.viewpoint != "A" && o.viewpoint != "B") throw UsageError("--viewpoint must be A or B");
  return o;
}

Setting ParseSetting(const std::string& name) {
  for (const Setting s : anchordb::sim::AllSettings()) {
    if (name == anchordb::sim::SettingName(s)) return s;
  }
  throw UsageError("unknown setting " + name + " (expected TA, SE, CA, DO, KI1, KI2 or SO)");
}

Eigen::Isometry3d ParseCamera(const std::string& text) {
  std::vector<double> values;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    std::size_t used = 0;
    double v = 0.0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || !std::isfinite(v)) throw UsageError("--camera: bad number '" + item + "'");
    values.push_back(v);
  }
  if (values.size() != 6) throw UsageError("--camera expects 6 numbers: eye x,y,z and target x,y,z");
  return anchordb::sim::LookAt(Eigen::Vector3d(values[0], values[1], values[2]),
                               Eigen::Vector3d(values[3], values[4], values[5]));
}

// A distinct, stable colour per object id (BGR); black for 0.
cv::Vec3b IdColour(std::int32_t id) {
  if (id == 0) return {0, 0, 0};
  const double hue = std::fmod(0.13 + id * 0.618033988749895, 1.0) * 6.0;
  const double saturation = id % 2 == 0 ? 0.75 : 0.55;
  const double value = id % 3 == 0 ? 0.75 : 0.95;
  const int sector = static_cast<int>(hue);
  const double f = hue - sector;
  const double p = value * (1 - saturation), q = value * (1 - saturation * f), t = value * (1 - saturation * (1 - f));
  double r = 0, g = 0, b = 0;
  switch (sector % 6) {
    case 0:
      r = value;
      g = t;
      b = p;
      break;
    case 1:
      r = q;
      g = value;
      b = p;
      break;
    case 2:
      r = p;
      g = value;
      b = t;
      break;
    case 3:
      r = p;
      g = q;
      b = value;
      break;
    case 4:
      r = t;
      g = p;
      b = value;
      break;
    default:
      r = value;
      g = p;
      b = q;
      break;
  }
  return {static_cast<uchar>(b * 255), static_cast<uchar>(g * 255), static_cast<uchar>(r * 255)};
}

// Brightness factor per pixel from the surface orientation (normals from neighbouring hits of the same object),
// so that faces of one object (the boards of a shelf) stay distinguishable in the id picture.
std::vector<float> Shading(const anchordb::sim::Frame& frame, const anchordb::PinholeIntrinsics& K) {
  const int w = frame.width, h = frame.height;
  const auto point = [&](int u, int v) {
    const double z = frame.true_depth_m[static_cast<std::size_t>(v) * w + u];
    return Eigen::Vector3d((u - K.cx) / K.fx * z, (v - K.cy) / K.fy * z, z);
  };
  const auto same = [&](int u0, int v0, int u1, int v1) {
    if (u1 < 0 || v1 < 0 || u1 >= w || v1 >= h) return false;
    return frame.object_id[static_cast<std::size_t>(v1) * w + u1] ==
           frame.object_id[static_cast<std::size_t>(v0) * w + u0];
  };
  const Eigen::Vector3d light = Eigen::Vector3d(-0.4, -0.6, -1.0).normalized();
  std::vector<float> shade(frame.true_depth_m.size(), 1.0f);
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      if (frame.object_id[static_cast<std::size_t>(v) * w + u] == 0) continue;
      Eigen::Vector3d du, dv;
      if (same(u, v, u + 1, v)) {
        du = point(u + 1, v) - point(u, v);
      } else if (same(u, v, u - 1, v)) {
        du = point(u, v) - point(u - 1, v);
      } else {
        continue;
      }
      if (same(u, v, u, v + 1)) {
        dv = point(u, v + 1) - point(u, v);
      } else if (same(u, v, u, v - 1)) {
        dv = point(u, v) - point(u, v - 1);
      } else {
        continue;
      }
      const Eigen::Vector3d n = du.cross(dv);
      if (n.norm() < 1e-12) continue;
      shade[static_cast<std::size_t>(v) * w + u] =
          static_cast<float>(0.35 + 0.65 * std::abs(n.normalized().dot(light)));
    }
  }
  return shade;
}

int Run(const Options& o) {
  anchordb::sim::Scene scene;
  Eigen::Isometry3d X_WorldCamera = Eigen::Isometry3d::Identity();
  if (o.setting) {
    const anchordb::sim::SettingScene setting = anchordb::sim::MakeSetting(ParseSetting(*o.setting), o.seed);
    scene = setting.scene;
    X_WorldCamera = o.viewpoint == "A" ? setting.X_WorldCameraA : setting.X_WorldCameraB;
  } else {
    std::ifstream file(*o.scene_path);
    if (!file) throw std::runtime_error("cannot open " + *o.scene_path);
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(file);
    } catch (const nlohmann::json::exception& e) {
      throw std::runtime_error(*o.scene_path + ": not valid JSON: " + e.what());
    }
    scene = anchordb::sim::SceneFromJson(j);
    X_WorldCamera = ParseCamera(*o.camera);
  }
  if (o.dump_scene_path) {
    std::ofstream out(*o.dump_scene_path);
    out << anchordb::sim::SceneToJson(scene).dump(2) << "\n";
    if (!out) throw std::runtime_error("cannot write " + *o.dump_scene_path);
    std::cout << "wrote " << *o.dump_scene_path << " (scene JSON, " << scene.objects.size() << " objects, "
              << scene.primitives.size() << " primitives)\n";
  }

  anchordb::sim::SensorModel sensor;
  sensor.noise = o.noise;
  const anchordb::PinholeIntrinsics K = anchordb::sim::KinectIntrinsics();
  const auto start = std::chrono::steady_clock::now();
  const anchordb::sim::Frame frame = anchordb::sim::Render(scene, K, X_WorldCamera, sensor, o.seed);
  const double render_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

  const std::vector<float> shade = Shading(frame, K);
  std::vector<std::uint16_t> depth(static_cast<std::size_t>(frame.width) * frame.height);
  std::vector<std::uint8_t> ids_rgb(depth.size() * 3);
  std::map<std::int32_t, std::size_t> pixels_per_id;
  std::size_t valid = 0;
  for (int v = 0; v < frame.height; ++v) {
    for (int u = 0; u < frame.width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * frame.width + u;
      depth[i] = frame.depth_mm[i];
      const cv::Vec3b colour = IdColour(frame.object_id[i]);  // BGR
      for (int c = 0; c < 3; ++c) ids_rgb[i * 3 + c] = static_cast<std::uint8_t>(colour[2 - c] * shade[i]);
      ++pixels_per_id[frame.object_id[i]];
      if (frame.depth_mm[i] != 0) ++valid;
    }
  }
  const std::string depth_path = o.out_prefix + "_depth.png";
  const std::string ids_path = o.out_prefix + "_ids.png";
  const auto write = [](const std::string& path, const std::string& png) {
    std::ofstream file(path, std::ios::binary);
    file.write(png.data(), static_cast<std::streamsize>(png.size()));
    if (!file) throw std::runtime_error("cannot write " + path);
  };
  write(depth_path, anchordb::sim::WritePngGrey16(depth, frame.width, frame.height));
  write(ids_path, anchordb::sim::WritePng(ids_rgb, frame.width, frame.height, 3, 8));

  const Eigen::Vector3d eye = X_WorldCamera.translation();
  const Eigen::Vector3d axis = X_WorldCamera.linear().col(2);
  std::printf(
      "rendered %dx%d, %zu primitives, camera at (%.3f, %.3f, %.3f) looking along (%.3f, %.3f, %.3f), "
      "%.1f ms\n",
      frame.width, frame.height, scene.primitives.size(), eye.x(), eye.y(), eye.z(), axis.x(), axis.y(), axis.z(),
      render_ms);
  std::printf("wrote %s (16-bit depth in mm, %zu of %zu pixels measured)\n", depth_path.c_str(), valid,
              frame.depth_mm.size());
  std::printf("wrote %s (object ids as colours)\n", ids_path.c_str());
  for (const auto& [id, count] : pixels_per_id) {
    std::string name = id == 0 ? "(nothing)" : "?";
    for (const anchordb::sim::Object& object : scene.objects) {
      if (object.id == id) name = object.name + " [" + object.kind + "]";
    }
    const cv::Vec3b c = IdColour(id);
    std::printf("  id %3d  %-28s %7zu px  colour #%02x%02x%02x\n", id, name.c_str(), count, c[2], c[1], c[0]);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return Run(ParseArgs(argc, argv));
  } catch (const UsageError& e) {
    std::cerr << "anchordb-render: " << e.what() << "\n" << kUsage;
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "anchordb-render: " << e.what() << "\n";
    return 1;
  }
}
