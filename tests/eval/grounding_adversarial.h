#pragma once
// An adversarial participant family for grounding (issue 17), written from a speaker model unlike
// tests/eval/grounding_eval.h's: rooms of 6-9 pieces at random positions (not a grid), always two or three pieces
// of one category, chairs, armchairs, sofas in any orientation (continuous yaw), shelves, wardrobes, cupboards and
// chests of drawers against a wall facing into the room; each speaker draws its own preference for the intrinsic
// frame (relative speakers 0-0.1, mixed 0.3-0.6, intrinsic 0.7-0.95 wherever the reference has a front), describes
// 10-20 pairs of neighbouring pieces (each located piece with its nearest piece), and takes the relative frame along
// its line of sight to the reference, not along the viewing direction; angles fall where they fall, borderline ones
// included. A description counts as right when it is matched to the intended pair or to another pair with the same
// categories for which the word holds in that relative frame or in the true intrinsic frame.
#include <cstdint>
#include <vector>

#include "engine/grounding/grounding.h"

namespace anchordb::eval::adversarial {

enum class Speaker { kRelative = 0, kMixed = 1, kIntrinsic = 2 };
const char* SpeakerName(Speaker s);

// The model configuration compared: the thesis' (uniform p(o), no ambiguity handling, no category floor),
// issue 17's sequential model (room orientation prior, ambiguity held with margin 0.02, category floor 0.05) and
// the joint model (engine/grounding/joint_model.h) with the same prior and floor, ambiguity margin JointOptions().
enum class Model { kThesis = 0, kIssue17 = 1, kJoint = 2 };
inline constexpr int kModelCount = 3;
const char* ModelName(Model m);

// The grounding parameters of the joint model as the service uses them (GroundingParams::model = kJoint).
engine::grounding::GroundingParams JointOptions();

struct RoomResult {
  int descriptions = 0, right = 0;
  bool graph_right = false;  // every piece's most probable category is its true one at the end
};

// One room and speaker (seeded), grounded by `model` at quality A (q = 0) or B (q = 1, one described piece
// misclassified).
RoomResult RunRoom(std::uint64_t seed, Speaker speaker, int quality, Model model);
// The same with explicit grounding parameters (the room prior is always used).
RoomResult RunRoom(std::uint64_t seed, Speaker speaker, int quality, const engine::grounding::GroundingParams& params);

// Prints one room's descriptions, their matches and the pieces' categories at the end to stderr (diagnosis).
void TraceRoom(std::uint64_t seed, Speaker speaker, int quality, const engine::grounding::GroundingParams& params);

struct Cell {
  int rooms = 0, graphs_right = 0;
  long descriptions = 0, right = 0;
  double worst_room_rate = 1.0;  // lowest share of right descriptions in one room
  double GraphRate() const { return rooms ? double(graphs_right) / rooms : 0.0; }
  double DescriptionRate() const { return descriptions ? double(right) / descriptions : 0.0; }
};

// cells[model][quality][speaker] over `rooms` rooms per speaker type (seeds first_seed...).
struct Table {
  Cell cells[kModelCount][2][3];
  Cell Over(Model m, int quality) const;  // all speakers
  double DescriptionRate(Model m) const;  // both qualities, all speakers
};
// Only the models in `models` are run (the other cells stay empty); `joint` replaces JointOptions() when given.
Table Evaluate(int rooms, std::uint64_t first_seed,
               const std::vector<Model>& models = {Model::kThesis, Model::kIssue17, Model::kJoint},
               const engine::grounding::GroundingParams* joint = nullptr);

}  // namespace anchordb::eval::adversarial
