#include "tests/eval/rooms_eval.h"

#include <chrono>
#include <random>

#include "engine/features/extraction.h"
#include "engine/features/features.h"
#include "engine/scene/projection.h"
#include "sim/rooms.h"

namespace anchordb::eval {
namespace {

double Since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

std::vector<engine::BaseSetting> RoomsBaseSet() {
  std::vector<engine::BaseSetting> set;
  for (int depth : {2, 4, 8}) {
    engine::BaseSetting s;
    s.kind = engine::BaseKind::kDTree;
    s.tree_max_depth = depth;
    set.push_back(s);
  }
  for (const auto& s : engine::SvmGrid({1.0, 10.0, 100.0}, {0.003, 0.01, 0.03})) set.push_back(s);
  for (int hidden : {20, 50}) {
    engine::BaseSetting s;
    s.kind = engine::BaseKind::kMlp;
    s.mlp_hidden = {hidden};
    s.mlp_iterations = 200;
    set.push_back(s);
  }
  return set;
}

RoomsData MakeRoomsData(const RoomsEvalOptions& o) {
  RoomsData out;
  const PinholeIntrinsics K{320, 240, 285.0, 285.0, 159.5, 119.5};
  const char* types[3] = {"fpfh", "shot", "spd"};
  const int words[3] = {o.words_fpfh, o.words_shot, o.words_spd};
  std::vector<std::vector<std::vector<float>>> descriptors(3);  // [type][room] flat
  std::vector<int> labels;
  engine::ExtractionParams params;
  params.voxel_m = 0.03;
  params.normal_radius_m = 0.07;
  params.feature_radius_m = 0.15;
  params.keypoint_voxel_m = 0.2;
  params.min_plane_points = 60;
  for (int c = 0; c < sim::kRoomCategoryCount; ++c) {
    for (int i = 0; i < o.rooms_per_category; ++i) {
      const sim::Room room = sim::MakeRoom(c, o.seed + static_cast<std::uint64_t>(i));
      auto t = std::chrono::steady_clock::now();
      std::vector<Eigen::Vector3f> cloud_m;
      for (std::size_t k = 0; k < room.X_WorldCamera.size(); ++k) {
        const sim::Frame f = sim::Render(room.scene, K, room.X_WorldCamera[k], sim::SensorModel{}, o.seed * 1000 + k);
        const auto points = engine::BackProjectRaw(f.depth_mm, 1000.0, K, room.X_WorldCamera[k]);
        cloud_m.insert(cloud_m.end(), points.begin(), points.end());
        ++out.keyframes;
      }
      out.render_seconds += Since(t);
      out.mean_points_per_room += static_cast<double>(cloud_m.size());
      t = std::chrono::steady_clock::now();
      const auto features = engine::ExtractFeatures(cloud_m, room.X_WorldCamera[0].translation(), {"fpfh", "shot", "spd"}, params);
      out.extract_seconds += Since(t);
      for (int ty = 0; ty < 3; ++ty) {
        descriptors[static_cast<std::size_t>(ty)].emplace_back();
        auto& flat = descriptors[static_cast<std::size_t>(ty)].back();
        for (const auto& f : features) {
          if (f.type == types[ty]) {
            flat.insert(flat.end(), f.descriptor.begin(), f.descriptor.end());
            out.mean_features_per_room[ty] += 1.0;
          }
        }
      }
      labels.push_back(c);
    }
  }
  const double rooms = static_cast<double>(labels.size());
  out.mean_points_per_room /= rooms;
  for (double& m : out.mean_features_per_room) m /= rooms;
  // One codebook per type from every room's features (k-means is unsupervised; the labels never enter it).
  for (int c = 0; c < sim::kRoomCategoryCount; ++c) out.bags.class_names.push_back(sim::RoomCategoryName(c));
  out.bags.labels = labels;
  for (int ty = 0; ty < 3; ++ty) {
    const int dims = *engine::FeatureTypeDims(types[ty]);
    std::vector<float> all;
    for (const auto& r : descriptors[static_cast<std::size_t>(ty)]) all.insert(all.end(), r.begin(), r.end());
    const engine::Codebook book = engine::BuildCodebook(all, dims, words[ty], o.seed);
    engine::FeatureMatrix bags(static_cast<Eigen::Index>(labels.size()), words[ty]);
    for (std::size_t r = 0; r < labels.size(); ++r) {
      const auto& flat = descriptors[static_cast<std::size_t>(ty)][r];
      std::vector<int> codewords;
      for (std::size_t at = 0; at + static_cast<std::size_t>(dims) <= flat.size(); at += static_cast<std::size_t>(dims)) {
        codewords.push_back(engine::NearestWord(book, std::vector<float>(flat.begin() + static_cast<std::ptrdiff_t>(at),
                                                                         flat.begin() + static_cast<std::ptrdiff_t>(at) + dims)));
      }
      const auto h = engine::BagOfWords(codewords, words[ty]);
      for (int w = 0; w < words[ty]; ++w) bags(static_cast<Eigen::Index>(r), w) = static_cast<float>(h[static_cast<std::size_t>(w)]);
    }
    out.bags.feature_types.push_back(types[ty]);
    out.bags.features.push_back(std::move(bags));
  }
  return out;
}

}  // namespace anchordb::eval
