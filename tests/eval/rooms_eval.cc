#include "tests/eval/rooms_eval.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <optional>
#include <random>
#include <stdexcept>

#include "engine/features/extraction.h"
#include "engine/features/features.h"
#include "engine/scene/projection.h"
#include "sim/rooms.h"
#include "tests/eval/mesh_rooms.h"

namespace anchordb::eval {
namespace {

constexpr std::size_t kCodebookSample = 15000;  // descriptors per type and fold that k-means sees

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
  std::optional<FurnitureMeshes> library;
  if (!o.furniture_dir.empty() && o.rooms_per_category > 0) {
    library = ReadFurnitureMeshes(o.furniture_dir);
    if (!library) throw std::runtime_error("the furniture meshes are missing in " + o.furniture_dir);
  }
  for (int c = 0; c < sim::kRoomCategoryCount; ++c) {
    for (int i = 0; i < o.rooms_per_category; ++i) {
      const std::uint64_t seed = o.seed + static_cast<std::uint64_t>(i);
      const MeshRoom mesh_room = library ? MakeMeshRoom(c, seed, *library) : MeshRoom{sim::MakeRoom(c, seed), {}, {}, {}};
      const sim::Room& room = mesh_room.room;
      auto t = std::chrono::steady_clock::now();
      std::vector<Eigen::Vector3f> cloud_m;
      for (std::size_t k = 0; k < room.X_WorldCamera.size(); ++k) {
        std::vector<std::uint16_t> depth_mm;
        if (library) {  // a noise seed per room and keyframe
          depth_mm = ScanWithMeshes(room.scene, mesh_room.meshes, K, room.X_WorldCamera[k], sim::SensorModel{},
                                    (o.seed * 1000 + k) * 7919 + seed * 16 + static_cast<std::uint64_t>(c));
        } else {
          depth_mm = sim::Render(room.scene, K, room.X_WorldCamera[k], sim::SensorModel{}, o.seed * 1000 + k).depth_mm;
        }
        const auto points = engine::BackProjectRaw(depth_mm, 1000.0, K, room.X_WorldCamera[k]);
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
  for (int c = 0; c < sim::kRoomCategoryCount; ++c) out.class_names.push_back(sim::RoomCategoryName(c));
  out.labels = labels;
  for (int ty = 0; ty < 3; ++ty) {
    out.feature_types.push_back(types[ty]);
    out.dims.push_back(*engine::FeatureTypeDims(types[ty]));
    out.words.push_back(words[ty]);
  }
  out.descriptors = std::move(descriptors);
  return out;
}

engine::TrainingSet BagsOfWords(const RoomsData& d, const std::vector<int>& codebook_rooms, std::uint64_t seed) {
  engine::TrainingSet bags;
  bags.class_names = d.class_names;
  bags.labels = d.labels;
  const std::size_t rooms = d.labels.size();
  for (std::size_t ty = 0; ty < d.feature_types.size(); ++ty) {
    const int dims = d.dims[ty], words = d.words[ty];
    std::vector<float> pooled;  // k-means is unsupervised; the labels never enter it, the test rooms neither
    for (int r : codebook_rooms) {
      const auto& flat = d.descriptors[ty][static_cast<std::size_t>(r)];
      pooled.insert(pooled.end(), flat.begin(), flat.end());
    }
    // k-means on a seeded sample of at most kCodebookSample descriptors (48 training rooms hold ~45,000 of each
    // type; the SHOT ones took most of the codebooks' time), every room's descriptors still coded below.
    const std::size_t n = pooled.size() / static_cast<std::size_t>(dims);
    if (n > kCodebookSample) {
      std::vector<std::size_t> order(n);
      for (std::size_t i = 0; i < n; ++i) order[i] = i;
      std::mt19937_64 rng(seed * 7919 + ty);
      for (std::size_t i = 0; i < kCodebookSample; ++i) {  // partial Fisher-Yates: the first kCodebookSample
        std::swap(order[i], order[i + static_cast<std::size_t>(rng() % (n - i))]);
      }
      std::vector<float> sample;
      sample.reserve(kCodebookSample * static_cast<std::size_t>(dims));
      for (std::size_t i = 0; i < kCodebookSample; ++i) {
        const auto at = pooled.begin() + static_cast<std::ptrdiff_t>(order[i] * static_cast<std::size_t>(dims));
        sample.insert(sample.end(), at, at + dims);
      }
      pooled = std::move(sample);
    }
    const engine::Codebook book = engine::BuildCodebook(pooled, dims, words, seed);
    engine::FeatureMatrix m(static_cast<Eigen::Index>(rooms), words);
    for (std::size_t r = 0; r < rooms; ++r) {
      const auto& flat = d.descriptors[ty][r];
      std::vector<int> codewords;
      for (std::size_t at = 0; at + static_cast<std::size_t>(dims) <= flat.size(); at += static_cast<std::size_t>(dims)) {
        codewords.push_back(engine::NearestWord(book, std::vector<float>(flat.begin() + static_cast<std::ptrdiff_t>(at),
                                                                         flat.begin() + static_cast<std::ptrdiff_t>(at) + dims)));
      }
      const auto h = engine::BagOfWords(codewords, words);
      for (int w = 0; w < words; ++w) m(static_cast<Eigen::Index>(r), w) = static_cast<float>(h[static_cast<std::size_t>(w)]);
    }
    bags.feature_types.push_back(d.feature_types[ty]);
    bags.features.push_back(std::move(m));
  }
  return bags;
}

std::vector<engine::TrainingSet> FoldBags(const RoomsData& d, const std::vector<int>& fold_of_room, std::uint64_t seed) {
  const int folds = fold_of_room.empty() ? 0 : *std::max_element(fold_of_room.begin(), fold_of_room.end()) + 1;
  std::vector<engine::TrainingSet> out;
  for (int f = 0; f < folds; ++f) {
    std::vector<int> training_rooms;
    for (std::size_t r = 0; r < fold_of_room.size(); ++r) {
      if (fold_of_room[r] != f) training_rooms.push_back(static_cast<int>(r));
    }
    out.push_back(BagsOfWords(d, training_rooms, seed + static_cast<std::uint64_t>(f)));
  }
  return out;
}

engine::TrainingSet OneType(const engine::TrainingSet& bags, std::size_t type) {
  engine::TrainingSet one = bags;
  one.feature_types = {bags.feature_types.at(type)};
  one.features = {bags.features.at(type)};
  return one;
}

engine::CrossValidationReport CrossValidateRooms(const std::vector<engine::TrainingSet>& fold_bags,
                                                 const engine::EsammeOptions& options,
                                                 const std::vector<int>& fold_of_room, int type) {
  return engine::CrossValidatePerFold(
      [&](int f) {
        const engine::TrainingSet& bags = fold_bags.at(static_cast<std::size_t>(f));
        return type < 0 ? bags : OneType(bags, static_cast<std::size_t>(type));
      },
      options, fold_of_room);
}

RoomsRun RunRooms(const RoomsEvalOptions& o) {
  RoomsRun run;
  run.data = MakeRoomsData(o);
  run.folds = engine::StratifiedFolds(run.data.labels, o.folds, o.seed);
  run.bags = FoldBags(run.data, run.folds, o.seed);  // codebooks from each fold's training rooms only
  run.all = CrossValidateRooms(run.bags, o.esamme, run.folds);
  return run;
}

void PrintRoomsRun(const char* name, const engine::CrossValidationReport& r, bool details) {
  const auto& e = r.test_error_per_round;
  double best = 1.0;
  for (double v : e) best = std::min(best, v);
  const std::size_t at20 = std::min<std::size_t>(19, e.size() - 1);
  std::printf("%-10s test error after 1 / 5 / 10 / 20 / last round: %.3f %.3f %.3f %.3f %.3f (worst fold at 20: %.3f), "
              "minimum %.3f, final-model error %.3f, train error at 20 %.3f\n",
              name, e[0], e[std::min<std::size_t>(4, e.size() - 1)], e[std::min<std::size_t>(9, e.size() - 1)], e[at20],
              e.back(), r.test_error_worst_fold_per_round[at20], best, r.test_error, r.train_error_per_round[at20]);
  if (!details) return;
  std::printf("\ntest error per round (mean over folds):");
  for (std::size_t i = 0; i < e.size(); ++i) std::printf("%s%.3f", i % 10 ? " " : "\n  ", e[i]);
  std::printf("\n\nconfusion (rows true, columns predicted):\n%14s", "");
  for (int c = 0; c < sim::kRoomCategoryCount; ++c) std::printf("%12.11s", sim::RoomCategoryName(c));
  for (int c = 0; c < sim::kRoomCategoryCount; ++c) {
    std::printf("\n%14s", sim::RoomCategoryName(c));
    for (int v : r.confusion[static_cast<std::size_t>(c)]) std::printf("%12d", v);
  }
  std::printf("\n\nshare of feature types among the chosen rounds:");
  for (const auto& [k, v] : r.feature_share) std::printf("  %s %.3f", k.c_str(), v);
  std::printf("\nshare of classifier kinds:");
  for (const auto& [k, v] : r.kind_share) std::printf("  %s %.3f", k.c_str(), v);
  std::printf("\n\n");
}

}  // namespace anchordb::eval
