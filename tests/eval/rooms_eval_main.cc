// Prints the room categorisation evaluation (thesis 4.3.3) on synthetic rooms beside the thesis' figures.
//   anchordb_eval_rooms [--rooms_per_category 10] [--rounds 30] [--seed 1] [--update thesis|sklearn]
//                       [--selection maximum|roulette|weights] [--sample_factor 0.6] [--cache FILE]
//                       [--variant box|mesh] [--furniture DIR]
// --variant mesh: the rooms furnished from the furniture meshes (tests/eval/mesh_rooms.h) of DIR (default
// $ANCHORDB_SHARED_DATA/aws_small_house/furniture_converted, else ../shared/data/...); box: the box-built rooms.
// --cache keeps every room's descriptors in FILE (written on the first run, read on later ones: codebooks and
// boosting rerun).
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <sstream>
#include <string>

#include "tests/eval/rooms_eval.h"

using namespace anchordb;

namespace {

// Every room's descriptors as binary: counts and header, then per type and room its float count and floats.
void SaveRooms(const std::string& path, const eval::RoomsData& d) {
  std::ofstream out(path, std::ios::binary);
  auto put = [&](const auto& v) { out.write(reinterpret_cast<const char*>(&v), sizeof(v)); };
  put(static_cast<std::uint64_t>(d.labels.size()));
  put(d.keyframes);
  put(d.mean_points_per_room);
  put(d.extract_seconds);
  put(d.render_seconds);
  for (double m : d.mean_features_per_room) put(m);
  for (int l : d.labels) put(l);
  for (const auto& type : d.descriptors) {
    for (const auto& room : type) {
      put(static_cast<std::uint64_t>(room.size()));
      out.write(reinterpret_cast<const char*>(room.data()), static_cast<std::streamsize>(room.size() * sizeof(float)));
    }
  }
}

// Reads SaveRooms' file into `d`, which holds the class names, types, dims and words already.
bool LoadRooms(const std::string& path, eval::RoomsData& d) {
  std::ifstream in(path, std::ios::binary);
  auto get = [&](auto& v) { return static_cast<bool>(in.read(reinterpret_cast<char*>(&v), sizeof(v))); };
  std::uint64_t rooms = 0;
  if (!get(rooms) || rooms > 100000) return false;
  get(d.keyframes);
  get(d.mean_points_per_room);
  get(d.extract_seconds);
  get(d.render_seconds);
  for (double& m : d.mean_features_per_room) get(m);
  d.labels.assign(rooms, 0);
  for (int& l : d.labels) get(l);
  d.descriptors.assign(d.feature_types.size(), std::vector<std::vector<float>>(rooms));
  for (auto& type : d.descriptors) {
    for (auto& room : type) {
      std::uint64_t count = 0;
      if (!get(count) || count > (1u << 28)) return false;
      room.resize(count);
      in.read(reinterpret_cast<char*>(room.data()), static_cast<std::streamsize>(count * sizeof(float)));
    }
  }
  return static_cast<bool>(in);
}

}  // namespace

int main(int argc, char** argv) {
  eval::RoomsEvalOptions o;
  std::string cache;
  bool mesh = false;
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
    else if (key == "--variant" && (value == "box" || value == "mesh")) mesh = value == "mesh";
    else if (key == "--furniture") o.furniture_dir = value, mesh = true;
    else {
      std::fprintf(stderr, "unknown option %s\n", key.c_str());
      return 2;
    }
  }
  o.esamme.base = eval::RoomsBaseSet();
  o.esamme.seed = o.seed;
  if (mesh && o.furniture_dir.empty()) {
    const char* data = std::getenv("ANCHORDB_SHARED_DATA");
    o.furniture_dir = std::string(data ? data : "../shared/data") + "/aws_small_house/furniture_converted";
  }
  eval::RoomsData data;
  bool cached = false;
  if (!cache.empty()) {
    data = eval::MakeRoomsData([&] {  // the room-independent fields (types, dims, words) without rendering
      eval::RoomsEvalOptions none = o;
      none.rooms_per_category = 0;
      return none;
    }());
    cached = LoadRooms(cache, data);
  }
  if (!cached) {
    try {
      data = eval::MakeRoomsData(o);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s\n", e.what());
      return 1;
    }
    if (!cache.empty()) SaveRooms(cache, data);
  } else {
    std::printf("(descriptors read from %s)\n", cache.c_str());
  }
  const int rooms = static_cast<int>(data.labels.size());
  std::printf("Room categorisation (thesis 4.3.3) on %d synthetic %s rooms (%d per category, seed %llu), %d keyframes "
              "(320x240, Kinect-like sensor), %.0f points per room;\nfeatures per room: fpfh %.0f, shot %.0f, spd %.1f; "
              "render %.1f s, extraction %.1f s in all (%.3f s per keyframe's share)\n",
              rooms, o.furniture_dir.empty() ? "box-built" : "mesh-furnished", o.rooms_per_category,
              static_cast<unsigned long long>(o.seed), data.keyframes, data.mean_points_per_room,
              data.mean_features_per_room[0], data.mean_features_per_room[1], data.mean_features_per_room[2],
              data.render_seconds, data.extract_seconds, data.extract_seconds / data.keyframes);
  std::printf("E-SAMME: %zu base settings (dtree x3, svm x9, mlp x2), %d rounds, selection %s, z_f %.2f, update %s, "
              "%d-fold stratified CV, codebooks per fold from its training rooms\nthesis KF-3D (114 real rooms): test "
              "error levels at 0.34 after ~20 rounds; FPFH alone 0.38, SHOT 0.49 (minima)\n\n",
              o.esamme.base.size(), o.esamme.rounds, engine::SelectionName(o.esamme.selection), o.esamme.sample_factor,
              engine::WeightUpdateName(o.esamme.update), o.folds);
  const auto folds = engine::StratifiedFolds(data.labels, o.folds, o.seed);
  auto t = std::chrono::steady_clock::now();
  const auto bags = eval::FoldBags(data, folds, o.seed);
  std::printf("(codebooks and bags of words of %d folds: %.1f s)\n", o.folds,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count());
  t = std::chrono::steady_clock::now();
  eval::PrintRoomsRun("all three", eval::CrossValidateRooms(bags, o.esamme, folds), true);
  std::printf("(cross-validation of all three types: %.1f s)\n", std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count());
  for (std::size_t ty = 0; ty < data.feature_types.size(); ++ty) {
    eval::PrintRoomsRun(data.feature_types[ty].c_str(), eval::CrossValidateRooms(bags, o.esamme, folds, static_cast<int>(ty)), false);
  }
  return 0;
}
