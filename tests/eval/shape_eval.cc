#include "tests/eval/shape_eval.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "engine/cloud/cloud_io.h"
#include "engine/shapes/virtual_scan.h"
#include "sim/renderer.h"
#include "sim/sensor_artefacts.h"
#include "tests/eval/seeded_rng.h"

namespace anchordb::eval {
namespace {

namespace fs = std::filesystem;
using engine::LabelledCloud;
using Points = std::vector<Eigen::Vector3f>;
using Clock = std::chrono::steady_clock;

std::string DataRoot() {
  const char* env = std::getenv("ANCHORDB_SHARED_DATA");
  return env ? env : "../shared/data";
}

std::string ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("shared data missing: cannot read " + path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

Points LoadPcd(const std::string& relative, float scale) {
  Points out;
  for (const auto& p : engine::DecodeCloud(ReadAll(DataRoot() + "/" + relative), 10'000'000).points) {
    if (p.allFinite()) out.push_back(p * scale);
  }
  return out;
}

double Seconds(Clock::time_point since) { return std::chrono::duration<double>(Clock::now() - since).count(); }

// Keeps the points on one side of a random vertical plane through the cloud: `keep` of them.
Points CutAway(const Points& pts, double keep, SeededRng& rng) {
  const double a = rng.Uniform(0, 2 * M_PI);
  const Eigen::Vector3f d(static_cast<float>(std::cos(a)), static_cast<float>(std::sin(a)), 0);
  std::vector<float> s;
  for (const auto& p : pts) s.push_back(p.dot(d));
  std::vector<float> sorted = s;
  const std::size_t k = std::min(sorted.size() - 1, static_cast<std::size_t>(keep * sorted.size()));
  std::nth_element(sorted.begin(), sorted.begin() + k, sorted.end());
  Points out;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (s[i] <= sorted[k]) out.push_back(pts[i]);
  }
  return out;
}

void AddBox(engine::TriangleMesh& m, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) {
  const int base = static_cast<int>(m.vertices_m.size());
  for (int i = 0; i < 8; ++i) {
    m.vertices_m.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
  }
  const int faces[12][3] = {{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1},
                            {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
  for (const auto& f : faces) m.triangles.emplace_back(base + f[0], base + f[1], base + f[2]);
}

struct FurnitureMesh {
  std::string category, name;
  engine::TriangleMesh mesh;
};

std::vector<FurnitureMesh> LoadFurniture(const std::vector<std::string>& only) {
  const fs::path root = fs::path(DataRoot()) / "aws_small_house/furniture_converted";
  if (!fs::is_directory(root)) throw std::runtime_error("shared data missing: " + root.string());
  std::vector<FurnitureMesh> out;
  for (const auto& dir : fs::directory_iterator(root)) {
    if (!dir.is_directory()) continue;
    const std::string category = dir.path().filename().string();
    if (!only.empty() && std::find(only.begin(), only.end(), category) == only.end()) continue;
    for (const auto& f : fs::directory_iterator(dir.path())) {
      if (f.path().extension() != ".obj") continue;
      out.push_back(FurnitureMesh{category, f.path().stem().string(), engine::ParseObj(ReadAll(f.path().string()))});
    }
  }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
    return std::tie(a.category, a.name) < std::tie(b.category, b.name);
  });
  return out;
}

// One test scan of `m`: a view between the training azimuths, Kinect noise, and per `kind` a cut-away part (1),
// clutter (2: a floor patch and a box beside the piece) or both (3). Clutter points stay in the segment.
Points Scan(const FurnitureMesh& m, double azimuth, double elevation, double distance_factor, int kind,
            std::uint64_t seed) {
  SeededRng rng(seed ^ 0x5bd1e995ULL);
  engine::TriangleMesh scene = m.mesh;
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(1e9f), hi = -lo;
  for (const auto& v : m.mesh.vertices_m) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  if (kind & 2) {
    const float margin = 0.15f;
    AddBox(scene, Eigen::Vector3f(lo.x() - margin, lo.y() - margin, lo.z() - 0.02f),
           Eigen::Vector3f(hi.x() + margin, hi.y() + margin, lo.z()));
    const double a = rng.Uniform(0, 2 * M_PI);
    const Eigen::Vector3f c = 0.5f * (lo + hi);
    const Eigen::Vector3f e = 0.5f * (hi - lo);
    const Eigen::Vector3f at(c.x() + (e.x() + 0.12f) * static_cast<float>(std::cos(a)),
                             c.y() + (e.y() + 0.12f) * static_cast<float>(std::sin(a)), lo.z());
    const float s = static_cast<float>(rng.Uniform(0.12, 0.25));
    AddBox(scene, at - Eigen::Vector3f(s / 2, s / 2, 0), at + Eigen::Vector3f(s / 2, s / 2, s));
  }
  const auto pose = engine::ScanViewpoints(m.mesh, 1, azimuth, elevation, distance_factor)[0];
  const engine::ScanCamera cam;
  const std::vector<double> ideal = engine::RenderMeshDepth(scene, Eigen::Isometry3d::Identity(), cam, pose);
  // The sim's Kinect v1 measurement stage (noise, quantisation, lateral jitter, flying pixels, dropouts).
  const sim::SensorModel sensor;
  std::mt19937_64 white_rng(seed ^ 0x9e3779b97f4a7c15ULL);
  std::normal_distribution<double> normal;
  std::vector<double> white(ideal.size());
  for (auto& w : white) w = normal(white_rng);
  std::vector<double> in_range = ideal;
  for (auto& z : in_range) {
    if (z < sensor.min_range_m || z > sensor.max_range_m) z = 0;
  }
  std::vector<std::uint16_t> depth_mm;
  sim::detail::MeasureDepth(sensor, cam.width, cam.height, seed, in_range, white, depth_mm);
  std::vector<double> measured(depth_mm.size());
  for (std::size_t i = 0; i < depth_mm.size(); ++i) measured[i] = depth_mm[i] * 0.001;
  Points pts = engine::DepthToWorldPoints(measured, cam, pose);
  if (kind & 2) {  // the floor is cut at 2 cm as a segmentation would (its top face lies at lo.z())
    Points kept;
    for (const auto& p : pts) {
      if (p.z() > lo.z() + 0.02f) kept.push_back(p);
    }
    pts = kept;
  }
  if (kind & 1) pts = CutAway(pts, rng.Uniform(0.65, 0.85), rng);
  return pts;
}

Points TestScan(const FurnitureMesh& m, int view, int views, int kind, std::uint64_t seed) {
  SeededRng rng(seed);
  const double azimuth = (view + 0.5) * 2 * M_PI / views + rng.Uniform(-0.1, 0.1);
  const double elevation = (view % 2 == 0) ? 0.3 : 0.75;
  return Scan(m, azimuth, elevation, rng.Uniform(1.1, 1.8), kind, seed);
}

struct TestCase {
  std::string category;
  Points points;
};

Confusion NewConfusion(const std::vector<std::string>& categories) {
  Confusion c;
  c.categories = categories;
  c.counts.assign(categories.size(), std::vector<int>(categories.size() + 1, 0));
  return c;
}

void Count(Confusion& c, const std::string& truth, const std::string& predicted) {
  const auto index = [&](const std::string& s) {
    return static_cast<std::size_t>(std::find(c.categories.begin(), c.categories.end(), s) - c.categories.begin());
  };
  const std::size_t t = index(truth);
  if (t >= c.categories.size()) return;
  c.counts[t][std::min(index(predicted), c.categories.size())] += 1;
}

DatasetResult Run(const std::string& name, const std::vector<LabelledCloud>& train, const std::vector<TestCase>& tests,
                  const std::vector<std::string>& categories, const ShapeEvalConfig& config, DatasetResult* accumulate) {
  DatasetResult r;
  r.name = name;
  r.ours.confusion = NewConfusion(categories);
  r.pcl.confusion = NewConfusion(categories);
  auto t0 = Clock::now();
  const engine::ShapeModel model = engine::TrainShapeModel(train, config.params);
  r.ours.train_s = Seconds(t0);
  std::fprintf(stderr, "%s: %zu training clouds, ours trained in %.1f s\n", name.c_str(), train.size(), r.ours.train_s);
  t0 = Clock::now();
  for (const auto& t : tests) Count(r.ours.confusion, t.category, engine::Verify(model, t.points).best);
  r.ours.predict_s_per_sample = Seconds(t0) / std::max<std::size_t>(1, tests.size());
  if (config.run_pcl) {
    r.ran_pcl = true;
    t0 = Clock::now();
    const engine::PclIsm ism(train, config.pcl);
    r.pcl.train_s = Seconds(t0);
    std::fprintf(stderr, "%s: PCL ISM trained in %.1f s\n", name.c_str(), r.pcl.train_s);
    t0 = Clock::now();
    Confusion by_peak = NewConfusion(categories), by_centre = NewConfusion(categories);
    for (const auto& t : tests) {
      const auto answer = ism.Classify(t.points, false);
      Count(by_peak, t.category, answer.best);
      std::string centre_best;
      double best = 0;
      for (std::size_t c = 0; c < answer.centre_density.size(); ++c) {
        if (answer.centre_density[c] > best) {
          best = answer.centre_density[c];
          centre_best = ism.categories()[c];
        }
      }
      Count(by_centre, t.category, centre_best);
    }
    r.pcl.predict_s_per_sample = Seconds(t0) / std::max<std::size_t>(1, tests.size());
    r.pcl.confusion = by_peak.Accuracy() >= by_centre.Accuracy() ? by_peak : by_centre;
  }
  if (accumulate) {
    for (auto [from, to] : {std::pair{&r.ours, &accumulate->ours}, std::pair{&r.pcl, &accumulate->pcl}}) {
      for (std::size_t i = 0; i < categories.size(); ++i) {
        for (std::size_t j = 0; j <= categories.size(); ++j) to->confusion.counts[i][j] += from->confusion.counts[i][j];
      }
      to->train_s += from->train_s;
      to->predict_s_per_sample = from->predict_s_per_sample;
    }
    accumulate->ran_pcl = r.ran_pcl;
  }
  return r;
}

std::vector<std::string> CategoriesOf(const std::vector<FurnitureMesh>& meshes) {
  std::vector<std::string> out;
  for (const auto& m : meshes) {
    if (out.empty() || out.back() != m.category) out.push_back(m.category);
  }
  return out;
}

// The 12 virtual scans of each mesh (azimuths 0, 30, ... 330 deg, elevation 0.5 rad) with the sim's noise
// (`noise`), or the engine's noiseless VirtualScans.
std::vector<LabelledCloud> TrainingScans(const std::vector<FurnitureMesh>& meshes, const std::string& except,
                                         bool noise) {
  std::vector<LabelledCloud> out;
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    const auto& m = meshes[i];
    if (m.name == except) continue;
    std::vector<Points> scans;
    if (noise) {
      for (int v = 0; v < 12; ++v) scans.push_back(Scan(m, 2 * M_PI * v / 12, 0.5, 1.5, 0, 7777 + i * 12 + v));
    } else {
      scans = engine::VirtualScans(m.mesh, 12, engine::ScanCamera{});
    }
    for (auto& scan : scans) {
      if (scan.size() >= 10) out.push_back(LabelledCloud{m.category, std::move(scan)});
    }
  }
  return out;
}

std::vector<TestCase> TestScans(const FurnitureMesh& m, const ShapeEvalConfig& config, std::size_t mesh_index) {
  std::vector<TestCase> out;
  for (int v = 0; v < config.test_views_per_mesh; ++v) {
    Points pts = TestScan(m, v, config.test_views_per_mesh, v % 4, config.seed * 1000003 + mesh_index * 101 + v);
    if (pts.size() >= 10) out.push_back(TestCase{m.category, std::move(pts)});
  }
  return out;
}

// The size figures of the verification's size term, for the tuning dump.
nlohmann::json SizeFigures(const Points& pts) {
  const engine::CloudSize s = engine::MeasureCloudSize(pts);
  return {{"n", pts.size()}, {"height", s.height_m}, {"length", s.length_m}, {"width", s.width_m}};
}

}  // namespace

void DumpFurnitureViews(const ShapeEvalConfig& config, const std::vector<std::uint64_t>& seeds, std::ostream& out,
                        bool leave_one_out) {
  const auto meshes = LoadFurniture(config.categories);
  for (const auto& m : meshes) {  // (a single mesh's scans: noise seeds differ from the training's, sizes hardly)
    for (const auto& t : TrainingScans({m}, "", config.train_noise)) {
      out << nlohmann::json{{"kind", "train"}, {"category", t.category}, {"mesh", m.name}, {"size", SizeFigures(t.points_m)}}
          << "\n";
    }
  }
  const auto test = [&](const char* kind, const engine::ShapeModel& model, const ShapeEvalConfig& c, std::size_t i) {
    for (const auto& t : TestScans(meshes[i], c, i)) {
      const auto v = engine::Verify(model, t.points);
      std::vector<double> weights;
      for (const auto& s : v.scores) weights.push_back(s.weight);
      out << nlohmann::json{{"kind", kind}, {"seed", c.seed}, {"category", t.category}, {"mesh", meshes[i].name},
                            {"best", v.best}, {"keypoints", v.keypoints}, {"weights", weights}, {"size", SizeFigures(t.points)}}
          << "\n" << std::flush;
    }
  };
  ShapeEvalConfig c = config;
  if (leave_one_out) {  // seeds[0]: per mesh of a category with several, the model trained on every other mesh
    std::map<std::string, int> per_category;
    for (const auto& m : meshes) ++per_category[m.category];
    c.seed = seeds.at(0);
    int held_out = -1;
    for (std::size_t i = 0; i < meshes.size(); ++i) {
      if (per_category[meshes[i].category] < 2) continue;
      ++held_out;
      if (held_out < config.loo_first || (config.loo_count >= 0 && held_out >= config.loo_first + config.loo_count)) continue;
      test("loo", engine::TrainShapeModel(TrainingScans(meshes, meshes[i].name, config.train_noise), config.params), c, i);
    }
    return;
  }
  const engine::ShapeModel model = engine::TrainShapeModel(TrainingScans(meshes, "", config.train_noise), config.params);
  for (const std::uint64_t seed : seeds) {
    c.seed = seed;
    for (std::size_t i = 0; i < meshes.size(); ++i) test("test", model, c, i);
  }
  nlohmann::json cats;
  for (const auto& category : model.categories) cats.push_back(category.name);
  out << nlohmann::json{{"kind", "categories"}, {"categories", cats}} << "\n";
}

int Confusion::Total() const {
  int n = 0;
  for (const auto& row : counts) {
    for (int v : row) n += v;
  }
  return n;
}

double Confusion::Accuracy() const {
  int right = 0;
  for (std::size_t i = 0; i < counts.size(); ++i) right += counts[i][i];
  return Total() ? static_cast<double>(right) / Total() : 0.0;
}

double Confusion::CategoryAccuracy(std::size_t c) const {
  int n = 0;
  for (int v : counts[c]) n += v;
  return n ? static_cast<double>(counts[c][c]) / n : 0.0;
}

ShapeEvalConfig FullShapeEvalConfig() {
  ShapeEvalConfig c;
  c.pair_params.voxel_m = 0.01;
  c.pair_params.normal_radius_m = 0.15;
  c.pair_params.keypoint_spacing_m = 0.04;
  c.pair_params.shot_radius_m = 0.40;
  c.pair_params.sphere_radius_m = 0.15;
  c.pair_params.codebook_size = 200;
  c.pair_params.max_keypoints = 600;
  // PCL's ISM on the furniture scans: sampling 2 cm (the tutorial's) takes minutes per model on 216 clouds of
  // ~20k points; 6 cm keeps its training within the run, normals and FPFH as in the tutorial.
  c.pcl.sampling_m = 0.06;
  return c;
}

ShapeEvalConfig QuickShapeEvalConfig() {
  ShapeEvalConfig c = FullShapeEvalConfig();
  c.variants_per_test_cloud = 4;
  c.test_views_per_mesh = 4;
  c.params.max_keypoints = 400;
  c.pair_params.max_keypoints = 300;
  c.pair_pcl.sampling_m = 0.04;
  c.pcl.sampling_m = 0.10;
  return c;
}

bool PclTestPairPresent() {
  return fs::exists(DataRoot() + "/pcl_test/ism_train.pcd") && fs::exists(DataRoot() + "/pcl_test/ism_test.pcd") &&
         fs::exists(DataRoot() + "/pcl_test/bun0.pcd") && fs::exists(DataRoot() + "/pcl_test/bun4.pcd");
}

bool FurnitureMeshesPresent() { return fs::is_directory(DataRoot() + "/aws_small_house/furniture_converted"); }

DatasetResult EvaluatePclTestPair(const ShapeEvalConfig& config) {
  const std::vector<std::string> categories = {"ism_object", "bunny"};
  const std::vector<LabelledCloud> train = {{"ism_object", LoadPcd("pcl_test/ism_train.pcd", 0.01f)},
                                            {"bunny", LoadPcd("pcl_test/bun0.pcd", 10.0f)}};
  const std::vector<std::pair<std::string, Points>> test_clouds = {{"ism_object", LoadPcd("pcl_test/ism_test.pcd", 0.01f)},
                                                                   {"bunny", LoadPcd("pcl_test/bun4.pcd", 10.0f)}};
  std::vector<TestCase> tests;
  SeededRng rng(config.seed);
  for (const auto& [category, cloud] : test_clouds) {
    tests.push_back(TestCase{category, cloud});
    for (int v = 1; v < config.variants_per_test_cloud; ++v) {
      Points pts;
      std::normal_distribution<float> noise(0.0f, 0.004f);
      std::mt19937_64 g(config.seed * 31 + v);
      for (const auto& p : cloud) {
        if (rng.Chance(0.8)) pts.push_back(p + Eigen::Vector3f(noise(g), noise(g), noise(g)));
      }
      if (v % 2 == 0) pts = CutAway(pts, 0.8, rng);
      tests.push_back(TestCase{category, std::move(pts)});
    }
  }
  ShapeEvalConfig pair = config;
  pair.params = config.pair_params;
  pair.pcl = config.pair_pcl;
  return Run("pcl_test_pair", train, tests, categories, pair, nullptr);
}

DatasetResult EvaluateFurnitureViews(const ShapeEvalConfig& config) {
  const auto meshes = LoadFurniture(config.categories);
  std::vector<TestCase> tests;
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    for (auto& t : TestScans(meshes[i], config, i)) tests.push_back(std::move(t));
  }
  return Run("furniture_unseen_views", TrainingScans(meshes, "", config.train_noise), tests, CategoriesOf(meshes), config, nullptr);
}

DatasetResult EvaluateFurnitureLeaveOneMeshOut(const ShapeEvalConfig& config) {
  const auto meshes = LoadFurniture(config.categories);
  const auto categories = CategoriesOf(meshes);
  DatasetResult total;
  total.name = "furniture_leave_one_mesh_out";
  total.ours.confusion = NewConfusion(categories);
  total.pcl.confusion = NewConfusion(categories);
  std::map<std::string, int> per_category;
  for (const auto& m : meshes) ++per_category[m.category];
  int held_out = -1;
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    if (per_category[meshes[i].category] < 2) continue;
    ++held_out;
    if (held_out < config.loo_first || (config.loo_count >= 0 && held_out >= config.loo_first + config.loo_count)) continue;
    std::fprintf(stderr, "leave-one-mesh-out %d: %s\n", held_out, meshes[i].name.c_str());
    Run(total.name, TrainingScans(meshes, meshes[i].name, config.train_noise), TestScans(meshes[i], config, i), categories, config, &total);
  }
  return total;
}

std::string ResultTable(const DatasetResult& r) {
  std::ostringstream out;
  const auto& cats = r.ours.confusion.categories;
  out << "### " << r.name << " (" << r.ours.confusion.Total() << " test clouds)\n\n";
  out << "| category | ours | PCL ISM |\n|---|---|---|\n";
  char buf[64];
  for (std::size_t c = 0; c < cats.size(); ++c) {
    std::snprintf(buf, sizeof buf, "| %.2f | %s |\n", r.ours.confusion.CategoryAccuracy(c),
                  r.ran_pcl ? std::to_string(r.pcl.confusion.CategoryAccuracy(c)).substr(0, 4).c_str() : "-");
    out << "| " << cats[c] << " " << buf;
  }
  const auto pcl_figure = [&](double v, const char* format) {
    char b[32];
    std::snprintf(b, sizeof b, format, v);
    return r.ran_pcl ? std::string(b) : std::string("-");
  };
  const auto worst = [&](const Confusion& m) {
    std::size_t w = 0;
    for (std::size_t c = 1; c < cats.size(); ++c) w = m.CategoryAccuracy(c) < m.CategoryAccuracy(w) ? c : w;
    return w;
  };
  std::snprintf(buf, sizeof buf, "| %.3f | %s |\n", r.ours.confusion.Accuracy(),
                pcl_figure(r.pcl.confusion.Accuracy(), "%.3f").c_str());
  out << "| **all** " << buf;
  const std::size_t ours_worst = worst(r.ours.confusion), pcl_worst = worst(r.pcl.confusion);
  out << "| worst category | " << cats[ours_worst] << " "
      << std::to_string(r.ours.confusion.CategoryAccuracy(ours_worst)).substr(0, 4) << " | "
      << (r.ran_pcl ? cats[pcl_worst] + " " + std::to_string(r.pcl.confusion.CategoryAccuracy(pcl_worst)).substr(0, 4)
                    : std::string("-"))
      << " |\n";
  std::snprintf(buf, sizeof buf, "| %.2f | %s |\n", r.ours.train_s, pcl_figure(r.pcl.train_s, "%.2f").c_str());
  out << "| train [s] " << buf;
  std::snprintf(buf, sizeof buf, "| %.3f | %s |\n", r.ours.predict_s_per_sample,
                pcl_figure(r.pcl.predict_s_per_sample, "%.3f").c_str());
  out << "| predict [s / cloud] " << buf;
  for (const auto* m : {&r.ours, &r.pcl}) {
    if (m == &r.pcl && !r.ran_pcl) break;
    out << "\nConfusion (" << (m == &r.ours ? "ours" : "PCL ISM") << "; rows true, columns predicted, last: none)\n\n|";
    for (const auto& c : cats) out << " | " << c.substr(0, 6);
    out << " | none |\n|";
    for (std::size_t c = 0; c < cats.size() + 2; ++c) out << "---|";
    out << "\n";
    for (std::size_t i = 0; i < cats.size(); ++i) {
      out << "| " << cats[i];
      for (int v : m->confusion.counts[i]) out << " | " << v;
      out << " |\n";
    }
  }
  return out.str();
}

std::string ResultJson(const DatasetResult& r) {
  nlohmann::json j;
  j["dataset"] = r.name;
  for (const auto& [key, m] : {std::pair{"ours", &r.ours}, std::pair{"pcl_ism", &r.pcl}}) {
    if (std::string(key) == "pcl_ism" && !r.ran_pcl) continue;
    j[key] = {{"accuracy", m->confusion.Accuracy()}, {"train_s", m->train_s},
              {"predict_s_per_cloud", m->predict_s_per_sample}, {"confusion", m->confusion.counts},
              {"categories", m->confusion.categories}};
  }
  return j.dump();
}

}  // namespace anchordb::eval
