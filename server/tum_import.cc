// `anchordb import tum`: a TUM RGB-D sequence into a map through the scene and octomap services.
#include "server/tum_import.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "schema/error.h"
#include "schema/json_io.h"
#include "services/audit/audit_service.h"
#include "services/grid/grid_service.h"
#include "services/octomap/octomap_service.h"
#include "services/scene/scene_service.h"

namespace anchordb::server {
namespace {

namespace fs = std::filesystem;

// The fields of a non-comment line, or empty for a blank / '#' line.
std::vector<std::string> Fields(const std::string& line) {
  std::vector<std::string> fields;
  std::istringstream in(line);
  for (std::string f; in >> f;) fields.push_back(f);
  if (!fields.empty() && fields[0][0] == '#') fields.clear();
  return fields;
}

double Number(const std::string& text, const std::string& where) {
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !std::isfinite(v)) throw std::invalid_argument(where + ": not a number: '" + text + "'");
  return v;
}

int PositiveInt(const std::string& text, const std::string& flag, int lo) {
  const double v = Number(text, flag);
  if (v != std::floor(v) || v < lo || v > 1e9) {
    throw std::invalid_argument(flag + ": expected an integer >= " + std::to_string(lo) + ", got " + text);
  }
  return static_cast<int>(v);
}

std::ifstream OpenList(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument("cannot read " + path.string() + " (not a TUM RGB-D sequence directory?)");
  return in;
}

// Width, height of a 16-bit grayscale PNG (its IHDR chunk); throws for anything else.
std::pair<int, int> PngSize16(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument("missing depth image " + path.string());
  unsigned char h[26] = {};
  in.read(reinterpret_cast<char*>(h), sizeof(h));
  static const unsigned char kMagic[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (in.gcount() != sizeof(h) || !std::equal(kMagic, kMagic + 8, h) || std::string(h + 12, h + 16) != "IHDR") {
    throw std::invalid_argument(path.string() + ": not a PNG");
  }
  const auto be32 = [&](int at) { return (h[at] << 24) | (h[at + 1] << 16) | (h[at + 2] << 8) | h[at + 3]; };
  if (h[24] != 16 || h[25] != 0) {
    throw std::invalid_argument(path.string() + ": a TUM depth image is a 16-bit grayscale PNG (bit depth " +
                                std::to_string(h[24]) + ", colour type " + std::to_string(h[25]) + ")");
  }
  return {be32(16), be32(20)};
}

std::string ReadBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument("missing depth image " + path.string());
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The ground-truth pose nearest `stamp_s` (poses sorted by stamp), or null beyond max_dt_s.
const TumPose* Nearest(const std::vector<TumPose>& poses, double stamp_s, double max_dt_s) {
  const auto it = std::lower_bound(poses.begin(), poses.end(), stamp_s,
                                   [](const TumPose& p, double s) { return p.stamp_s < s; });
  const TumPose* best = nullptr;
  if (it != poses.end()) best = &*it;
  if (it != poses.begin() && (!best || stamp_s - std::prev(it)->stamp_s < best->stamp_s - stamp_s)) best = &*std::prev(it);
  if (!best || std::abs(best->stamp_s - stamp_s) > max_dt_s) return nullptr;
  return best;
}

std::int64_t StampNs(double stamp_s) { return static_cast<std::int64_t>(std::llround(stamp_s * 1e9)); }

}  // namespace

std::vector<TumImage> ParseTumImageList(std::istream& in, const std::string& file) {
  std::vector<TumImage> images;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    const std::vector<std::string> f = Fields(line);
    if (f.empty()) continue;
    const std::string where = file + " line " + std::to_string(n);
    if (f.size() != 2) throw std::invalid_argument(where + ": expected 'timestamp path', got '" + line + "'");
    images.push_back({Number(f[0], where), f[1]});
  }
  return images;
}

std::vector<TumPose> ParseTumGroundTruth(std::istream& in, const std::string& file) {
  std::vector<TumPose> poses;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    const std::vector<std::string> f = Fields(line);
    if (f.empty()) continue;
    const std::string where = file + " line " + std::to_string(n);
    if (f.size() != 8) throw std::invalid_argument(where + ": expected 'timestamp tx ty tz qx qy qz qw', got '" + line + "'");
    double v[8];
    for (int i = 0; i < 8; ++i) v[i] = Number(f[i], where);
    Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    if (std::abs(q.norm() - 1.0) > 1e-2) throw std::invalid_argument(where + ": quaternion not of unit norm");
    TumPose p;
    p.stamp_s = v[0];
    p.X_WorldCamera.position_m = {v[1], v[2], v[3]};
    p.X_WorldCamera.orientation = q.normalized();
    poses.push_back(p);
  }
  std::sort(poses.begin(), poses.end(), [](const TumPose& a, const TumPose& b) { return a.stamp_s < b.stamp_s; });
  return poses;
}

PinholeIntrinsics TumCamera(const std::string& name) {
  // The benchmark's calibrated depth (= rgb) intrinsics per recording setup, 640 x 480.
  PinholeIntrinsics k;
  if (name == "fr1") k.fx = 517.3, k.fy = 516.5, k.cx = 318.6, k.cy = 255.3;
  else if (name == "fr2") k.fx = 520.9, k.fy = 521.0, k.cx = 325.1, k.cy = 249.7;
  else if (name == "fr3") k.fx = 535.4, k.fy = 539.2, k.cx = 320.1, k.cy = 247.6;
  else throw std::invalid_argument("--camera: expected fr1, fr2 or fr3, got " + name);
  return k;
}

namespace {

// The frames to import, each with its pose, every file checked before anything is stored.
struct PlannedFrame {
  const TumImage* image;
  const TumPose* pose;
};
struct ImportPlan {
  std::vector<PlannedFrame> frames;
  std::size_t without_pose = 0;  // depth frames with no ground-truth pose within max_dt_s
  PinholeIntrinsics camera;      // o.camera with the sequence's image size
};

ImportPlan PlanImport(const fs::path& dir, const std::vector<TumImage>& depth, const std::vector<TumPose>& poses,
                      const TumImportOptions& o) {
  ImportPlan plan;
  plan.camera = o.camera;
  for (std::size_t i = 0; i < depth.size(); i += static_cast<std::size_t>(o.every)) {
    if (o.max_frames > 0 && plan.frames.size() >= static_cast<std::size_t>(o.max_frames)) break;
    const TumPose* pose = Nearest(poses, depth[i].stamp_s, o.max_dt_s);
    if (!pose) {
      ++plan.without_pose;
      continue;
    }
    const auto [w, h] = PngSize16(dir / depth[i].path);
    if (plan.frames.empty()) plan.camera.width = w, plan.camera.height = h;
    if (w != plan.camera.width || h != plan.camera.height) {
      throw std::invalid_argument(depth[i].path + ": " + std::to_string(w) + " x " + std::to_string(h) +
                                  ", the sequence's first frame is " + std::to_string(plan.camera.width) + " x " +
                                  std::to_string(plan.camera.height));
    }
    plan.frames.push_back({&depth[i], pose});
  }
  if (plan.frames.empty()) {
    throw std::invalid_argument("no depth frame of depth.txt (" + std::to_string(depth.size()) +
                                " lines) has a ground-truth pose within " + std::to_string(o.max_dt_s) + " s");
  }
  return plan;
}

// What an import did, for the audit trail and the last line of its output.
struct ImportCounts {
  std::size_t frames_imported, frames_in_depth_txt, frames_without_pose, keyframes, keyframes_in_octomap;
  std::int64_t first_scene, last_scene;
  double seconds;
};

// The import's summary: an audit entry (actor cli, action map.import_tum) and the last two output lines.
void RecordImport(storage::Store& store, const fs::path& dir, const TumImportOptions& o, const ImportCounts& n,
                  const services::OctomapInfo& info, std::ostream& out) {
  json::Json summary = {{"sequence", fs::absolute(dir).lexically_normal().string()},
                        {"map", o.map},
                        {"frames_imported", n.frames_imported},
                        {"frames_in_depth_txt", n.frames_in_depth_txt},
                        {"frames_without_pose", n.frames_without_pose},
                        {"scenes", {n.first_scene, n.last_scene}},
                        {"keyframes", n.keyframes},
                        {"keyframes_in_octomap", n.keyframes_in_octomap},
                        {"octomap_version", info.version},
                        {"octomap_leaves", info.metadata.leaves},
                        {"octomap_occupied_leaves", info.metadata.occupied_leaves},
                        {"seconds", n.seconds}};
  services::AuditEntry entry;
  entry.actor = "cli", entry.action = "map.import_tum", entry.map = o.map, entry.after_json = summary.dump();
  services::AuditService(store).Record(std::move(entry));
  char line[240];
  std::snprintf(line, sizeof(line),
                "imported %zu frames (%zu without a pose within %.3f s skipped) in %.1f s (%.1f frames/s): scenes "
                "%lld-%lld, %zu keyframes, octomap v%lld with %zu leaves (%zu occupied)\n",
                n.frames_imported, n.frames_without_pose, o.max_dt_s, n.seconds, n.frames_imported / std::max(n.seconds, 1e-9),
                static_cast<long long>(n.first_scene), static_cast<long long>(n.last_scene), n.keyframes,
                static_cast<long long>(info.version), info.metadata.leaves, info.metadata.occupied_leaves);
  out << line << summary.dump() << "\n";
}

}  // namespace

void ImportTum(const Config& config, const TumImportOptions& o, std::ostream& out) {
  const fs::path dir(o.dir);
  if (!fs::is_directory(dir)) throw std::invalid_argument("--dir: no directory " + o.dir);
  std::ifstream depth_list = OpenList(dir / "depth.txt");
  std::ifstream truth_list = OpenList(dir / "groundtruth.txt");
  const std::vector<TumImage> depth = ParseTumImageList(depth_list, "depth.txt");
  const std::vector<TumPose> poses = ParseTumGroundTruth(truth_list, "groundtruth.txt");
  if (poses.empty()) throw std::invalid_argument("groundtruth.txt holds no pose");
  const ImportPlan planned = PlanImport(dir, depth, poses, o);
  const std::vector<PlannedFrame>& plan = planned.frames;
  const std::size_t without_pose = planned.without_pose;
  const PinholeIntrinsics& camera = planned.camera;

  storage::Store store(StoreOptionsOf(config.server));
  services::CapabilityOptions capability = config.capabilities;
  services::GridService grid(store, capability.limits, capability.grid);
  try {
    grid.GetMap(o.map);
  } catch (const Error& e) {
    if (e.code() != ErrorCode::kNotFound) throw;
    throw std::invalid_argument("unknown map '" + o.map + "' in " + config.server.db + " (create it first: POST /v1/maps)");
  }
  services::SceneService scenes(store, capability.scene, capability.merge);
  capability.octomap.from_keyframes = true;  // the import builds the tree from the keyframes it stores
  services::OctomapService octomap(store, capability.octomap, SystemClock::Instance(), &grid);

  out << "importing " << plan.size() << " of " << depth.size() << " depth frames from " << o.dir << " into map "
      << o.map << " (every " << o.every << ", fx " << camera.fx << " fy " << camera.fy << " cx " << camera.cx
      << " cy " << camera.cy << ", " << o.depth_scale << " units/m)\n" << std::flush;
  const auto start = std::chrono::steady_clock::now();
  std::size_t keyframes = 0;
  services::FollowReport tree;
  std::int64_t first_scene = 0, last_scene = 0;
  for (std::size_t k = 0; k < plan.size(); ++k) {
    const PlannedFrame& p = plan[k];
    services::OpenSceneRequest open;
    open.camera = camera;
    open.X_MapCamera = p.pose->X_WorldCamera;
    open.params.depth_scale = o.depth_scale;
    open.merge = o.merge;
    open.stamp_ns = StampNs(p.image->stamp_s);
    const services::SceneInfo scene = scenes.Open(o.map, open);
    const std::string png = ReadBytes(dir / p.image->path);
    services::FrameInput frame;
    frame.body = png;
    frame.stamp_ns = open.stamp_ns;
    if (scenes.AddFrame(o.map, scene.id, frame).keyframe) ++keyframes;
    if (scenes.Close(o.map, scene.id).keyframe) ++keyframes;
    const services::FollowReport followed = octomap.Follow(o.map);
    tree.keyframes_integrated += followed.keyframes_integrated;
    if (k == 0) first_scene = scene.id;
    last_scene = scene.id;
    const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    char line[200];
    std::snprintf(line, sizeof(line), "frame %zu/%zu  stamp %.6f  scene %lld  %.1f frames/s\n", k + 1, plan.size(),
                  p.image->stamp_s, static_cast<long long>(scene.id), (k + 1) / std::max(elapsed_s, 1e-9));
    out << line << std::flush;
  }
  scenes.PersistAll();
  octomap.CommitPending();  // the last keyframes of the sequence (octomap_keyframes_per_commit)
  const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const services::OctomapInfo info = octomap.Get(o.map);
  const ImportCounts counts{plan.size(), depth.size(), without_pose, keyframes, tree.keyframes_integrated, first_scene,
                            last_scene, elapsed_s};
  RecordImport(store, dir, o, counts, info, out);
}

int ImportTumCommand(const std::vector<std::string>& args, const std::map<std::string, std::string>& environment) {
  TumImportOptions o;
  std::string every, max_frames, camera, fx, fy, cx, cy, scale, max_dt, db;
  std::vector<std::string> rest;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (TakeOption(args, i, "--db", db)) {  // settings take --db=FILE only; the import also takes --db FILE
      rest.push_back("--db=" + db);
      continue;
    }
    if (TakeOption(args, i, "--dir", o.dir) || TakeOption(args, i, "--map", o.map) ||
        TakeOption(args, i, "--every", every) || TakeOption(args, i, "--max-frames", max_frames) ||
        TakeOption(args, i, "--camera", camera) || TakeOption(args, i, "--fx", fx) || TakeOption(args, i, "--fy", fy) ||
        TakeOption(args, i, "--cx", cx) || TakeOption(args, i, "--cy", cy) ||
        TakeOption(args, i, "--depth-scale", scale) || TakeOption(args, i, "--max-dt", max_dt)) {
      continue;
    }
    if (args[i] == "--merge") o.merge = true;
    else if (o.dir.empty() && args[i].rfind("--", 0) != 0) o.dir = args[i];
    else rest.push_back(args[i]);
  }
  if (o.dir.empty()) throw std::invalid_argument("import tum needs the sequence directory (--dir DIR)");
  if (o.map.empty()) throw std::invalid_argument("import tum needs --map ID");
  if (!every.empty()) o.every = PositiveInt(every, "--every", 1);
  if (!max_frames.empty()) o.max_frames = PositiveInt(max_frames, "--max-frames", 0);
  // The camera: named, else guessed from TUM's directory names (rgbd_dataset_freiburg2_...), else Freiburg 1.
  if (camera.empty()) {
    const std::string name = fs::path(o.dir).lexically_normal().filename().string() + fs::path(o.dir).string();
    camera = name.find("freiburg2") != std::string::npos ? "fr2" : name.find("freiburg3") != std::string::npos ? "fr3" : "fr1";
  }
  o.camera = TumCamera(camera);
  const auto positive = [](const std::string& text, const std::string& flag) {
    const double v = Number(text, flag);
    if (v <= 0) throw std::invalid_argument(flag + ": must be > 0, got " + text);
    return v;
  };
  if (!fx.empty()) o.camera.fx = positive(fx, "--fx");
  if (!fy.empty()) o.camera.fy = positive(fy, "--fy");
  if (!cx.empty()) o.camera.cx = Number(cx, "--cx");
  if (!cy.empty()) o.camera.cy = Number(cy, "--cy");
  if (!scale.empty()) o.depth_scale = positive(scale, "--depth-scale");
  if (!max_dt.empty()) o.max_dt_s = positive(max_dt, "--max-dt");
  try {
    json::CheckId(o.map, "map");
  } catch (const Error& e) {
    throw std::invalid_argument(std::string("--map: ") + e.what());
  }
  const Config config = LoadConfig(rest, environment);
  RequireExistingDatabase(config.server.db);
  ImportTum(config, o, std::cout);
  return 0;
}

}  // namespace anchordb::server
