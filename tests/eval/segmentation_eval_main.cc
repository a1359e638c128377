// Furniture segmentation end to end (issue 16): segmentation precision / recall and category accuracy on box-built
// and mesh-furnished rooms, and the lost-key scenario answered relative to detected furniture.
//   anchordb_eval_segmentation [--rooms N] [--lost_key_runs N] [--first_seed N] [--data DIR] [--core_density X]
// (--core_density 0: without the cut at bridges of flying pixels, as before it)
// (ANCHORDB_BIN: the server binary; DIR default ../shared/data, or $ANCHORDB_SHARED_DATA)
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <optional>
#include <string>

#include "tests/eval/segmentation_eval.h"
#include "tests/support/real_data_files.h"

namespace {

void Print(const char* name, const anchordb::eval::SegmentationScore& s) {
  const double total = std::accumulate(s.seconds.begin(), s.seconds.end(), 0.0);
  std::printf("%-12s rooms %d  pieces %d  segments %d  precision %.3f  recall %.3f  category accuracy %.3f  "
              "bridges cut %d  segmentation %.2f s per room cloud\n",
              name, s.rooms, s.pieces, s.segments, s.precision(), s.recall(), s.category_accuracy(), s.bridges_cut,
              s.rooms ? total / s.rooms : 0.0);
  for (const std::string& m : s.misses) std::printf("    %s\n", m.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  int rooms = 10, runs = 20;
  std::uint64_t seed = 1;
  std::string data = anchordb::testing::SharedDataPath("");
  anchordb::engine::segmentation::SegmentationParams params;
  std::optional<double> core_density;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--rooms")) rooms = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--lost_key_runs")) runs = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--first_seed")) seed = std::strtoull(argv[i + 1], nullptr, 10);
    else if (!std::strcmp(argv[i], "--data")) data = argv[i + 1];
    else if (!std::strcmp(argv[i], "--core_density")) core_density = params.core_density = std::atof(argv[i + 1]);
  }
  if (rooms > 0) {
    Print("box rooms", anchordb::eval::EvaluateBoxRooms(rooms, seed, params));
    const auto mesh = anchordb::eval::EvaluateMeshRooms(rooms, seed, data + "/aws_small_house/furniture_converted", params);
    if (mesh) Print("mesh rooms", *mesh);
    else std::printf("mesh rooms   skipped: %s/aws_small_house/furniture_converted is absent\n", data.c_str());
  }
  if (runs > 0) {
    const auto lk = anchordb::eval::EvaluateLostKey(runs, seed, core_density);
    std::printf("lost key     runs %d  answer names the detected table %d  (table segmented %d)\n", lk.runs, lk.named_table,
                lk.segmented_table);
    for (std::size_t i = 0; i < lk.sentences.size(); ++i) {
      std::printf("    seed %zu: %s   [%s]\n", static_cast<std::size_t>(seed + i), lk.sentences[i].c_str(), lk.segments[i].c_str());
    }
  }
  return 0;
}
