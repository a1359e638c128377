#pragma once
// World knowledge of the grounding model (thesis 5.2, 5.3.2, 5.3.4): the furniture categories with their
// vehicle / opposite nature and the words that name them, and the reference-frame prior
// P(frame | nature of the reference, orientation of the reference, relative position of the located object) for
// each assessment scheme. The defaults are engine/grounding/categories.json and frame_prior.json, embedded at
// build time; the same formats load from text (a file the server reads, or one stored with a graph). Loaders
// throw anchordb::Error(kInvalidArgument) naming the offending entry.
//
// Directions are those seen from the viewpoint (the relative frame): left_of / right_of = to the viewer's left /
// right of the reference, in_front_of = between the viewer and the reference, behind = farther from the viewer.
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace anchordb::engine::grounding {

enum class Relation : std::uint8_t { kLeftOf = 0, kRightOf = 1, kInFrontOf = 2, kBehind = 3 };
inline constexpr int kRelationCount = 4;
// "left_of", "right_of", "in_front_of", "behind".
const char* RelationId(Relation r);
// "to the left of", "to the right of", "in front of", "behind".
const char* RelationPhrase(Relation r);

// Where a piece's intrinsic front points, seen from the viewpoint (thesis 5.3.2: O = {left, right, front, back};
// front = the front faces the viewer, back = it faces away).
enum class Orientation : std::uint8_t { kLeft = 0, kRight = 1, kFront = 2, kBack = 3 };
inline constexpr int kOrientationCount = 4;
const char* OrientationId(Orientation o);

// Vehicle: intrinsic left/right as if sitting in the object; opposite: as if standing in front of it, facing it;
// none: no intrinsic front (a front assigned in conversation is read like a vehicle's, Algorithm 5 line 8).
enum class Nature : std::uint8_t { kVehicle = 0, kOpposite = 1, kNone = 2 };
inline constexpr int kNatureCount = 3;
const char* NatureId(Nature n);

enum class Frame : std::uint8_t { kRelative = 0, kIntrinsic = 1 };
const char* FrameId(Frame f);

// The relation, in the relative frame, that the word `word` means when spoken in the intrinsic frame of a reference
// of nature `nature` whose front points to `o`: I(r | intrinsic, o_ref) of eq. 5.1.
Relation IntrinsicToRelative(Relation word, Nature nature, Orientation o);
// The inverse: the intrinsic word for a located object at relative position `relative`.
Relation RelativeToIntrinsic(Relation relative, Nature nature, Orientation o);

// Where a piece of a category tends to face in a room (issue 17; engine/grounding/orientation_prior.h): with its
// back to the nearest wall, towards the nearest piece of another category (a chair at its table), into the room.
enum class FrontRule : std::uint8_t { kNone = 0, kBackToWall = 1, kFacePiece = 2, kFaceRoom = 3 };

struct FrontPrior {
  FrontRule rule = FrontRule::kNone;
  double weight = 0.0;     // share of p(o) the rule's direction gets; the rest is uniform (in [0, 1])
  double reach_m = 0.6;    // a wall or piece farther than this from the footprint does not count [m]
  std::string towards;     // kFacePiece: the category id faced ("table")
};

struct Category {
  std::string id;                  // "chest_of_drawers"
  std::string name;                // "chest of drawers": what the robot says
  Nature nature = Nature::kNone;
  std::vector<std::string> words;  // lowercase phrases a speaker may use
  FrontPrior front;                // the initial p(o) of a piece of this category
};

class CategoryTable {
 public:
  CategoryTable() = default;
  explicit CategoryTable(std::vector<Category> categories);  // validates (unique ids and words, non-empty)

  int size() const { return static_cast<int>(categories_.size()); }
  const Category& operator[](int i) const { return categories_[static_cast<std::size_t>(i)]; }
  const std::vector<Category>& all() const { return categories_; }
  // Index of the category with this id, or -1.
  int IndexOfId(std::string_view id) const;
  // Index of the category one of whose words (or id) is `phrase` (lowercase, single spaces), or -1.
  int IndexOfWord(std::string_view phrase) const;
  // Longest number of tokens in any word (the parser's look-ahead).
  int MaxWordTokens() const { return max_word_tokens_; }
  // "chair, armchair, ..." for error messages.
  std::string IdList() const;

 private:
  std::vector<Category> categories_;
  int max_word_tokens_ = 1;
};

// Assessment schemes of reference-frame use (thesis 5.3.4): the statistics of the study (S), a relative-preferring
// (R) and an intrinsic-preferring (I) distribution, and the uniform distribution of the 5.4 comparisons.
enum class Scheme : std::uint8_t { kStatistical = 0, kRelative = 1, kIntrinsic = 2, kUniform = 3 };
inline constexpr int kSchemeCount = 4;
const char* SchemeId(Scheme s);

class FramePrior {
 public:
  FramePrior();  // every dissociated cell 0.5 (uniform), for tests
  // P(frame | nature, o, r'): r' is the located object's relation to the reference in the relative frame;
  // P(relative) + P(intrinsic) = 1 in every cell, also where both frames happen to give the same word.
  double Probability(Scheme s, Frame f, Nature nature, Orientation o, Relation relative) const {
    return p_[Index(s, f, nature, o, relative)];
  }
  // Whether both frames give the same word at (nature, o, r') (e.g. a shelf facing the viewer).
  static bool FramesCoincide(Nature nature, Orientation o, Relation relative);
  void SetIntrinsic(Scheme s, Nature nature, Orientation o, Relation relative, double p_intrinsic);

 private:
  static std::size_t Index(Scheme s, Frame f, Nature n, Orientation o, Relation r) {
    return ((((static_cast<std::size_t>(s) * 2 + static_cast<std::size_t>(f)) * kNatureCount + static_cast<std::size_t>(n)) *
                 kOrientationCount + static_cast<std::size_t>(o)) * kRelationCount) + static_cast<std::size_t>(r);
  }
  std::array<double, kSchemeCount * 2 * kNatureCount * kOrientationCount * kRelationCount> p_{};
};

struct Knowledge {
  CategoryTable categories;
  FramePrior prior;
};

// Parsers of the two JSON formats (see the files for their shape).
CategoryTable LoadCategoryTable(std::string_view json_text);
FramePrior LoadFramePrior(std::string_view json_text);
// A document {"categories": <categories format>, "frame_prior": <frame prior format>}; either part may be
// omitted and then is the built-in default.
Knowledge LoadKnowledge(std::string_view json_text);
// Such a document checked (LoadKnowledge's errors) and completed with the built-in part it omits ("" gives both
// built-in tables): the knowledge a new graph stores, so that a later change of the defaults cannot change it.
std::string CompleteKnowledgeJson(std::string_view json_text);

// The embedded default files' text, and the knowledge they define.
std::string_view DefaultCategoriesJson();
std::string_view DefaultFramePriorJson();
const Knowledge& DefaultKnowledge();

}  // namespace anchordb::engine::grounding
