// Shape models beside PCL's ISM (issue 16, SPEC section 7: "shape-model verification of a segment no slower than
// PCL's ISM"): training time per model, verification per segment and detection per room cloud, both methods on the
// same clouds in the same run; prints one JSON document. Clouds: virtual scans (12 views) of the two test meshes
// (tests/support/furniture_meshes.h); segments: 10 other views; room: both pieces 2.5 m apart on a 5 x 5 m floor.
// Usage: anchordb_shapes_bench [repetitions=3]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/shapes/pcl_ism_peer.h"
#include "engine/shapes/shape_model.h"
#include "engine/shapes/virtual_scan.h"
#include "tests/support/furniture_meshes.h"

namespace {

using namespace anchordb;
using Points = std::vector<Eigen::Vector3f>;
using Clock = std::chrono::steady_clock;

Points View(const std::string& obj, double azimuth_rad, const Eigen::Vector3f& offset_m = {0, 0, 0}) {
  const engine::TriangleMesh mesh = engine::ParseObj(obj);
  const engine::ScanCamera cam;
  const auto pose = engine::ScanViewpoints(mesh, 1, azimuth_rad, 0.35)[0];
  Points points = engine::DepthToWorldPoints(engine::RenderMeshDepth(mesh, Eigen::Isometry3d::Identity(), cam, pose), cam, pose);
  for (auto& p : points) p += offset_m;
  return points;
}

template <typename F>
double Median(int repetitions, F&& fn) {
  std::vector<double> s;
  for (int i = 0; i < repetitions; ++i) {
    const auto t0 = Clock::now();
    fn();
    s.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
  }
  std::sort(s.begin(), s.end());
  return s[s.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const int repetitions = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  const std::vector<std::pair<std::string, std::string>> meshes = {{"table", testing::TableObj()},
                                                                   {"cabinet", testing::CabinetObj()}};
  std::vector<engine::LabelledCloud> train;
  for (const auto& [category, obj] : meshes) {
    for (auto& scan : engine::VirtualScans(engine::ParseObj(obj), 12, engine::ScanCamera{})) train.push_back({category, scan});
  }
  std::vector<Points> segments;
  for (int i = 0; i < 10; ++i) segments.push_back(View(meshes[i % 2].second, 0.3 + 0.6 * i));
  Points room = View(testing::TableObj(), 0.5, {1.0f, 1.0f, 0.0f});
  const Points cabinet = View(testing::CabinetObj(), 0.5, {3.5f, 1.0f, 0.0f});
  room.insert(room.end(), cabinet.begin(), cabinet.end());
  for (float x = 0; x <= 5.0f; x += 0.04f) {
    for (float y = 0; y <= 5.0f; y += 0.04f) room.push_back({x, y, 0.0f});
  }

  engine::ShapeModelParams params;
  params.codebook_size = 100;
  engine::ShapeModel model;
  const double ours_train_s = Median(1, [&] { model = engine::TrainShapeModel(train, params); });
  std::unique_ptr<engine::PclIsm> ism;
  const double pcl_train_s = Median(1, [&] { ism = std::make_unique<engine::PclIsm>(train, engine::PclIsmParams{}); });

  int ours_right = 0, pcl_right = 0;
  const double ours_verify_s = Median(repetitions, [&] {
    ours_right = 0;
    for (std::size_t i = 0; i < segments.size(); ++i) ours_right += engine::Verify(model, segments[i]).best == meshes[i % 2].first;
  }) / segments.size();
  const double pcl_verify_s = Median(repetitions, [&] {
    pcl_right = 0;
    for (std::size_t i = 0; i < segments.size(); ++i) pcl_right += ism->Classify(segments[i], true).best == meshes[i % 2].first;
  }) / segments.size();
  std::size_t ours_detections = 0;
  const double ours_detect_s = Median(repetitions, [&] { ours_detections = engine::Detect(model, room).size(); });
  const double pcl_detect_s = Median(repetitions, [&] { ism->Classify(room, false); });

  const nlohmann::json out = {
      {"bench", "shapes"},
      {"training_clouds", train.size()},
      {"segments", segments.size()},
      {"room_points", room.size()},
      {"train_s", {{"ours", ours_train_s}, {"pcl_ism", pcl_train_s}, {"ratio_ours_to_pcl", ours_train_s / pcl_train_s}}},
      {"verify_s_per_segment",
       {{"ours", ours_verify_s}, {"pcl_ism", pcl_verify_s}, {"ratio_ours_to_pcl", ours_verify_s / pcl_verify_s},
        {"ours_right", ours_right}, {"pcl_right", pcl_right}}},
      {"detect_s_per_room",
       {{"ours", ours_detect_s}, {"pcl_ism", pcl_detect_s}, {"ratio_ours_to_pcl", ours_detect_s / pcl_detect_s},
        {"ours_detections", ours_detections}}},
      {"notes", "PCL ISM: tutorial parameters scaled to metres (normals 0.25, FPFH 0.30, sampling 0.02); its detection "
                "is findObjects + findStrongestPeaks per class; medians of the repetitions"}};
  std::printf("%s\n", out.dump(2).c_str());
  return 0;
}
