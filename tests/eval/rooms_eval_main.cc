// Prints the room categorisation evaluation (thesis 4.3.3) on synthetic rooms beside the thesis' figures.
//   anchordb_eval_rooms [--rooms_per_category 10] [--rounds 30] [--seed 1] [--update thesis|sklearn]
//                       [--selection maximum|roulette|weights] [--sample_factor 0.6] [--cache FILE]
// --cache keeps the bags of words in FILE (written on the first run, read on later ones: only the boosting reruns).
#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "sim/rooms.h"
#include "tests/eval/rooms_eval.h"

using namespace anchordb;

namespace {

// The bags as text: a header line "rooms types words..." then per room its label and every type's histogram.
void SaveBags(const std::string& path, const eval::RoomsData& d) {
  std::ofstream out(path);
  out << d.bags.labels.size() << " " << d.keyframes << " " << d.mean_points_per_room << " " << d.extract_seconds;
  for (const auto& m : d.bags.features) out << " " << m.cols();
  out << "\n";
  for (std::size_t r = 0; r < d.bags.labels.size(); ++r) {
    out << d.bags.labels[r];
    for (const auto& m : d.bags.features) for (Eigen::Index w = 0; w < m.cols(); ++w) out << " " << m(static_cast<Eigen::Index>(r), w);
    out << "\n";
  }
}

bool LoadBags(const std::string& path, eval::RoomsData& d) {
  std::ifstream in(path);
  std::size_t rooms = 0;
  if (!(in >> rooms >> d.keyframes >> d.mean_points_per_room >> d.extract_seconds)) return false;
  std::vector<int> words(3);
  for (int& w : words) in >> w;
  d.bags.feature_types = {"fpfh", "shot", "spd"};
  for (int c = 0; c < sim::kRoomCategoryCount; ++c) d.bags.class_names.push_back(sim::RoomCategoryName(c));
  for (int w : words) d.bags.features.emplace_back(static_cast<Eigen::Index>(rooms), w);
  for (std::size_t r = 0; r < rooms; ++r) {
    int label = 0;
    in >> label;
    d.bags.labels.push_back(label);
    for (auto& m : d.bags.features) for (Eigen::Index w = 0; w < m.cols(); ++w) in >> m(static_cast<Eigen::Index>(r), w);
  }
  return static_cast<bool>(in);
}

void PrintRun(const char* name, const engine::CrossValidationReport& r, bool details) {
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

}  // namespace

int main(int argc, char** argv) {
  eval::RoomsEvalOptions o;
  std::string cache;
  o.esamme.rounds = 30;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--rooms_per_category") o.rooms_per_category = std::stoi(value);
    else if (key == "--rounds") o.esamme.rounds = std::stoi(value);
    else if (key == "--seed") o.seed = std::stoull(value);
    else if (key == "--update") o.esamme.update = engine::ParseWeightUpdate(value);
    else if (key == "--selection") o.esamme.selection = engine::ParseSelection(value);
    else if (key == "--sample_factor") o.esamme.sample_factor = std::stod(value);
    else if (key == "--cache") cache = value;
    else {
      std::fprintf(stderr, "unknown option %s\n", key.c_str());
      return 2;
    }
  }
  o.esamme.base = eval::RoomsBaseSet();
  o.esamme.seed = o.seed;
  eval::RoomsData data;
  if (cache.empty() || !LoadBags(cache, data)) {
    data = eval::MakeRoomsData(o);
    if (!cache.empty()) SaveBags(cache, data);
  } else {
    std::printf("(bags of words read from %s)\n", cache.c_str());
  }
  const int rooms = static_cast<int>(data.bags.labels.size());
  std::printf("Room categorisation (thesis 4.3.3) on %d synthetic rooms (%d per category, seed %llu), %d keyframes "
              "(320x240, Kinect-like sensor), %.0f points per room;\nfeatures per room: fpfh %.0f, shot %.0f, spd %.1f; "
              "render %.1f s, extraction %.1f s in all (%.3f s per keyframe's share)\n",
              rooms, o.rooms_per_category, static_cast<unsigned long long>(o.seed), data.keyframes, data.mean_points_per_room,
              data.mean_features_per_room[0], data.mean_features_per_room[1], data.mean_features_per_room[2],
              data.render_seconds, data.extract_seconds, data.extract_seconds / data.keyframes);
  std::printf("E-SAMME: %zu base settings (dtree x3, svm x9, mlp x2), %d rounds, selection %s, z_f %.2f, update %s, "
              "%d-fold stratified CV\nthesis KF-3D (114 real rooms): test error levels at 0.34 after ~20 rounds; FPFH alone "
              "0.38, SHOT 0.49 (minima)\n\n",
              o.esamme.base.size(), o.esamme.rounds, engine::SelectionName(o.esamme.selection), o.esamme.sample_factor,
              engine::WeightUpdateName(o.esamme.update), o.folds);
  const auto folds = engine::StratifiedFolds(data.bags.labels, o.folds, o.seed);
  const auto t = std::chrono::steady_clock::now();
  PrintRun("all three", engine::CrossValidate(data.bags, o.esamme, folds), true);
  std::printf("(cross-validation of all three types: %.1f s)\n", std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count());
  for (std::size_t ty = 0; ty < data.bags.feature_types.size(); ++ty) {
    engine::TrainingSet one = data.bags;
    one.feature_types = {data.bags.feature_types[ty]};
    one.features = {data.bags.features[ty]};
    PrintRun(data.bags.feature_types[ty].c_str(), engine::CrossValidate(one, o.esamme, folds), false);
  }
  return 0;
}
