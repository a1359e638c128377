#pragma once
// Room categorisation in the manner of thesis 4.3.3 on synthetic rooms (sim/rooms.h, box-built or furnished from the
// furniture meshes, tests/eval/mesh_rooms.h): each room scanned from its
// keyframes, the clouds merged in the map frame, FPFH / SHOT / SPD extracted (engine/features/extraction.h),
// codebooks by k-means, one bag of words per room and type, E-SAMME cross-validated over the rooms. The codebooks of
// a fold are built from that fold's training rooms only (the test rooms' descriptors never shape the words).
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
  // Empty: the box-built rooms (sim/rooms.h). Else the rooms furnished from the furniture meshes of this folder
  // (…/aws_small_house/furniture_converted; tests/eval/mesh_rooms.h), scanned with the sim's sensor model.
  std::string furniture_dir;
};

// MLPs, DTrees and an RBF SVM grid (the thesis used SVMs, DTrees and MLPs).
std::vector<engine::BaseSetting> RoomsBaseSet();

// Every room's descriptors, before any codebook.
struct RoomsData {
  std::vector<std::string> class_names;    // the six categories
  std::vector<int> labels;                 // per room
  std::vector<std::string> feature_types;  // fpfh, shot, spd
  std::vector<int> dims, words;            // per type: descriptor length, codebook size
  std::vector<std::vector<std::vector<float>>> descriptors;  // [type][room]: the room's descriptors back to back
  double render_seconds = 0.0;             // all rooms
  double extract_seconds = 0.0;            // all rooms (PCL)
  int keyframes = 0;
  double mean_points_per_room = 0.0;
  double mean_features_per_room[3] = {0, 0, 0};
};

// Renders every room and extracts its features. Throws std::runtime_error when options.furniture_dir is set and a
// mesh is missing there.
RoomsData MakeRoomsData(const RoomsEvalOptions& options);

// The bags of words of every room (feature types as in `data`), over one codebook per type built by seeded k-means
// from the descriptors of the rooms `codebook_rooms` only (a seeded sample of 15,000 of them when there are more).
engine::TrainingSet BagsOfWords(const RoomsData& data, const std::vector<int>& codebook_rooms, std::uint64_t seed);

// Per fold f, BagsOfWords over the rooms outside fold f (k-means seeded seed + f).
std::vector<engine::TrainingSet> FoldBags(const RoomsData& data, const std::vector<int>& fold_of_room, std::uint64_t seed);

// The set of one feature type (index into feature_types) of a bag set.
engine::TrainingSet OneType(const engine::TrainingSet& bags, std::size_t type);

// Cross-validation with fold f trained and tested on fold_bags[f] (and only the feature type `type`, if >= 0).
engine::CrossValidationReport CrossValidateRooms(const std::vector<engine::TrainingSet>& fold_bags,
                                                 const engine::EsammeOptions& options,
                                                 const std::vector<int>& fold_of_room, int type = -1);

// The tests' run: MakeRoomsData(options), options.folds stratified folds (seed options.seed), per-fold bags of words
// and the cross-validation of all feature types together.
struct RoomsRun {
  RoomsData data;
  std::vector<int> folds;
  std::vector<engine::TrainingSet> bags;
  engine::CrossValidationReport all;
};
RoomsRun RunRooms(const RoomsEvalOptions& options);

// Prints a cross-validation's test error after 1 / 5 / 10 / 20 / the last round (and the worst fold's, the minimum,
// the final models', the train error at 20) on one line headed `name`; with `details` also the error of every round,
// the confusion matrix (the six room categories) and the shares of feature types and classifier kinds.
void PrintRoomsRun(const char* name, const engine::CrossValidationReport& r, bool details);

}  // namespace anchordb::eval
