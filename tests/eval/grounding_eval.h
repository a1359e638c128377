#pragma once
// The grounding evaluation of thesis 5.4.2, rebuilt with synthetic participants. Each participant gets a generated
// scene of 6-8 furniture pieces on a 3 x 3 grid aligned with the view (as the thesis' furniture was aligned with
// the line of sight), with true categories and orientations, and describes 12-20 pairs of neighbouring pieces in
// random order, in the frame its speaker type chooses:
//   relative  - always the relative (viewer's) frame;
//   prior     - the intrinsic frame with the probability of the statistical frame prior of the knowledge table;
//   intrinsic - the intrinsic frame for every reference with an intrinsic front (with probability 0.85), else
//               the relative frame.
// The visual category distributions come in three qualities like figure 5.17: A correct and clear, B one piece
// misclassified with flatter distributions, C one confident mistake with flat distributions. Orientations are
// unknown to the model (uniform p(o)). The same participant (scene and descriptions) is grounded under every
// quality and condition (paired, as in the thesis).
#include <cstdint>
#include <string>
#include <vector>

#include "engine/grounding/grounding.h"

namespace anchordb::eval {

enum class Quality { kA = 0, kB = 1, kC = 2 };
enum class Speaker { kRelative = 0, kPrior = 1, kIntrinsic = 2 };
enum class Condition { kAdaptation = 0, kNoAdaptation = 1, kUniform = 2 };
const char* QualityName(Quality q);
const char* SpeakerName(Speaker s);
const char* ConditionName(Condition c);

struct TruePiece {
  int category = 0;
  engine::grounding::Orientation orientation = engine::grounding::Orientation::kFront;
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d extent_m = Eigen::Vector2d::Zero();
};

struct TrueDescription {
  int located = 0;    // vertex
  int reference = 0;  // vertex
  engine::grounding::Relation word = engine::grounding::Relation::kLeftOf;
  engine::grounding::Frame frame = engine::grounding::Frame::kRelative;
  bool frames_differ = true;  // false when both frames give this word
};

struct Participant {
  std::uint64_t seed = 0;
  Speaker speaker = Speaker::kRelative;
  engine::grounding::Viewpoint view;
  std::vector<TruePiece> pieces;
  std::vector<TrueDescription> descriptions;
  int misclassified = 0;  // the piece that qualities B and C get wrong
};

Participant MakeParticipant(std::uint64_t seed, Speaker speaker, const engine::grounding::Knowledge& knowledge);

// The visual analysis' p(f) for each piece, in the given quality (seeded by the participant).
std::vector<std::vector<double>> VisualCategories(const Participant& p, Quality q, int category_count);
// Mean entropy of the distributions [bits].
double MeanEntropyBits(const std::vector<std::vector<double>>& distributions);

struct TrialResult {
  int descriptions = 0;
  int descriptions_correct = 0;
  bool sequence_correct = false;
  int vertices = 0;
  int vertices_right = 0;
  int fronted = 0;             // pieces with an intrinsic front
  int orientations_right = 0;  // of those, argmax p(o) is the true orientation (unique)
  bool misclassified_right = false;  // the piece B / C got wrong has its true category at the end
  bool misclassified_wrong_at_start = false;
  int worst_rank_reverted = 0;  // largest rank (1 = best) among the final best hypothesis' ancestors
  int intrinsic_descriptions = 0;  // descriptions spoken in the intrinsic frame where the frames differ
  int held = 0;                 // descriptions found ambiguous when grounded (issue 17)
  int held_wrong = 0;           // of those, the best match at that moment was not the intended pair
  int unheld_wrong = 0;         // descriptions not held whose best match at that moment was not the intended pair
};

struct EvalOptions {
  engine::grounding::Model model = engine::grounding::Model::kSequential;  // kJoint: engine/grounding/joint_model.h
  engine::grounding::JointParams joint;
  int n_best = 100;
  double sigma = 3.0;
  double ambiguity_margin = 0.0;  // issue 17 (0 = the thesis' model)
  double category_floor = 0.0;
};

TrialResult RunTrial(const Participant& p, Quality q, Condition c, const engine::grounding::Knowledge& knowledge,
                     const EvalOptions& options);

struct Tally {
  long descriptions = 0, descriptions_correct = 0;
  long sequences = 0, sequences_correct = 0;
  long vertices = 0, vertices_right = 0;
  long fronted = 0, orientations_right = 0;
  long misclassified = 0, misclassified_corrected = 0;  // over trials whose misclassified piece started wrong
  int worst_rank_reverted = 0;
  long held = 0, held_wrong = 0, unheld_wrong = 0;
  void Add(const TrialResult& r);
  double DescriptionRate() const { return descriptions ? double(descriptions_correct) / descriptions : 0.0; }
  double SequenceRate() const { return sequences ? double(sequences_correct) / sequences : 0.0; }
  double VertexRate() const { return vertices ? double(vertices_right) / vertices : 0.0; }
  double OrientationRate() const { return fronted ? double(orientations_right) / fronted : 0.0; }
  double CorrectedRate() const { return misclassified ? double(misclassified_corrected) / misclassified : 0.0; }
};

// tallies[quality][condition][speaker]
struct Evaluation {
  Tally tallies[3][3][3];
  double entropy_bits[3] = {0, 0, 0};
  int participants_per_speaker = 0;
  Tally Over(Quality q, Condition c) const;  // all speakers
};

Evaluation Evaluate(int participants_per_speaker, std::uint64_t first_seed, const EvalOptions& options);

}  // namespace anchordb::eval
