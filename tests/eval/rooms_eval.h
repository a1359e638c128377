#pragma once
// Room categorisation in the manner of thesis 4.3.3 on synthetic rooms (sim/rooms.h): each room scanned from its
// keyframes, the clouds merged in the map frame, FPFH / SHOT / SPD extracted (engine/features/extraction.h),
// codebooks by k-means, one bag of words per room and type, E-SAMME cross-validated over the rooms.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/classification/cross_validation.h"

namespace anchordb::eval {

struct RoomsEvalOptions {
  int rooms_per_category = 10;
  std::uint64_t seed = 1;
  int words_fpfh = 40, words_shot = 40, words_spd = 12;
  int folds = 5;
  engine::EsammeOptions esamme;  // base empty: RoomsBaseSet()
};

// MLPs, DTrees and an RBF SVM grid (the thesis used SVMs, DTrees and MLPs).
std::vector<engine::BaseSetting> RoomsBaseSet();

struct RoomsData {
  engine::TrainingSet bags;          // feature types fpfh, shot, spd; classes the six categories
  double render_seconds = 0.0;       // all rooms
  double extract_seconds = 0.0;      // all rooms (PCL)
  int keyframes = 0;
  double mean_points_per_room = 0.0;
  double mean_features_per_room[3] = {0, 0, 0};
};

// Renders, extracts and builds the bags of words of every room.
RoomsData MakeRoomsData(const RoomsEvalOptions& options);

}  // namespace anchordb::eval
