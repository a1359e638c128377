#include "engine/grounding/knowledge.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <set>
#include <sstream>

#include "schema/error.h"

namespace anchordb::engine::grounding {
namespace {

using Json = nlohmann::json;

[[noreturn]] void Bad(const std::string& message, const std::string& field = {}) {
  throw Error(ErrorCode::kInvalidArgument, message, field);
}

// Unit vectors in the viewer's frame: x to the viewer's right, y away from the viewer.
struct Dir {
  int x, y;
  bool operator==(const Dir&) const = default;
};

Dir RelativeDir(Relation r) {
  switch (r) {
    case Relation::kLeftOf: return {-1, 0};
    case Relation::kRightOf: return {1, 0};
    case Relation::kInFrontOf: return {0, -1};
    case Relation::kBehind: return {0, 1};
  }
  return {0, 0};
}

Dir FrontDir(Orientation o) {
  switch (o) {
    case Orientation::kLeft: return {-1, 0};
    case Orientation::kRight: return {1, 0};
    case Orientation::kFront: return {0, -1};
    case Orientation::kBack: return {0, 1};
  }
  return {0, 0};
}

Relation RelationOfDir(Dir d) {
  for (int i = 0; i < kRelationCount; ++i) {
    if (RelativeDir(static_cast<Relation>(i)) == d) return static_cast<Relation>(i);
  }
  throw Error(ErrorCode::kInternal, "direction is not axis-aligned");
}

Json ParseJson(std::string_view text, const char* what) {
  Json j = Json::parse(text.begin(), text.end(), nullptr, false);
  if (j.is_discarded() || !j.is_object()) Bad(std::string(what) + " is not a JSON object");
  return j;
}

std::string NormalisePhrase(std::string_view text) {
  std::string out;
  bool space = false;
  for (char c : text) {
    const unsigned char u = static_cast<unsigned char>(c);
    if (std::isspace(u)) {
      space = !out.empty();
      continue;
    }
    if (space) out += ' ';
    space = false;
    out += static_cast<char>(std::tolower(u));
  }
  return out;
}

int TokenCount(const std::string& phrase) {
  int n = phrase.empty() ? 0 : 1;
  for (char c : phrase) n += c == ' ';
  return n;
}

}  // namespace

const char* RelationId(Relation r) {
  switch (r) {
    case Relation::kLeftOf: return "left_of";
    case Relation::kRightOf: return "right_of";
    case Relation::kInFrontOf: return "in_front_of";
    case Relation::kBehind: return "behind";
  }
  return "?";
}

const char* RelationPhrase(Relation r) {
  switch (r) {
    case Relation::kLeftOf: return "to the left of";
    case Relation::kRightOf: return "to the right of";
    case Relation::kInFrontOf: return "in front of";
    case Relation::kBehind: return "behind";
  }
  return "?";
}

const char* OrientationId(Orientation o) {
  switch (o) {
    case Orientation::kLeft: return "left";
    case Orientation::kRight: return "right";
    case Orientation::kFront: return "front";
    case Orientation::kBack: return "back";
  }
  return "?";
}

const char* NatureId(Nature n) {
  switch (n) {
    case Nature::kVehicle: return "vehicle";
    case Nature::kOpposite: return "opposite";
    case Nature::kNone: return "none";
  }
  return "?";
}

const char* FrameId(Frame f) { return f == Frame::kRelative ? "relative" : "intrinsic"; }

const char* SchemeId(Scheme s) {
  switch (s) {
    case Scheme::kStatistical: return "statistical";
    case Scheme::kRelative: return "relative";
    case Scheme::kIntrinsic: return "intrinsic";
    case Scheme::kUniform: return "uniform";
  }
  return "?";
}

Relation IntrinsicToRelative(Relation word, Nature nature, Orientation o) {
  const Dir f = FrontDir(o);
  switch (word) {
    case Relation::kInFrontOf: return RelationOfDir(f);
    case Relation::kBehind: return RelationOfDir({-f.x, -f.y});
    case Relation::kLeftOf:
    case Relation::kRightOf: {
      // Left of someone facing direction (x, y) is (-y, x). A vehicle's left is that of a person sitting in it
      // (facing its front); an opposite object's left is that of a person standing before it, facing it.
      Dir left = nature == Nature::kOpposite ? Dir{f.y, -f.x} : Dir{-f.y, f.x};
      if (word == Relation::kRightOf) left = {-left.x, -left.y};
      return RelationOfDir(left);
    }
  }
  return word;
}

Relation RelativeToIntrinsic(Relation relative, Nature nature, Orientation o) {
  for (int i = 0; i < kRelationCount; ++i) {
    const auto w = static_cast<Relation>(i);
    if (IntrinsicToRelative(w, nature, o) == relative) return w;
  }
  throw Error(ErrorCode::kInternal, "intrinsic mapping is not a bijection");
}

CategoryTable::CategoryTable(std::vector<Category> categories) : categories_(std::move(categories)) {
  if (categories_.empty()) Bad("the category table is empty", "categories");
  std::set<std::string> ids, words;
  for (Category& c : categories_) {
    if (c.id.empty() || !ids.insert(c.id).second) Bad("category id '" + c.id + "' is empty or repeated", "categories");
    if (c.name.empty()) c.name = c.id;
    for (std::string& w : c.words) {
      w = NormalisePhrase(w);
      if (w.empty()) Bad("category '" + c.id + "' has an empty word", "categories");
    }
    // The id is always a word of its own category.
    if (std::find(c.words.begin(), c.words.end(), c.id) == c.words.end()) c.words.push_back(c.id);
  }
  for (const Category& c : categories_) {
    for (const std::string& w : c.words) {
      if (!words.insert(w).second) Bad("the word '" + w + "' names more than one category", "categories");
      max_word_tokens_ = std::max(max_word_tokens_, TokenCount(w));
    }
  }
}

int CategoryTable::IndexOfId(std::string_view id) const {
  for (std::size_t i = 0; i < categories_.size(); ++i) {
    if (categories_[i].id == id) return static_cast<int>(i);
  }
  return -1;
}

int CategoryTable::IndexOfWord(std::string_view phrase) const {
  const std::string p = NormalisePhrase(phrase);
  for (std::size_t i = 0; i < categories_.size(); ++i) {
    for (const std::string& w : categories_[i].words) {
      if (w == p) return static_cast<int>(i);
    }
  }
  return -1;
}

std::string CategoryTable::IdList() const {
  std::string out;
  for (const Category& c : categories_) out += (out.empty() ? "" : ", ") + c.id;
  return out;
}

FramePrior::FramePrior() {
  for (int s = 0; s < kSchemeCount; ++s) {
    for (int n = 0; n < kNatureCount; ++n) {
      for (int o = 0; o < kOrientationCount; ++o) {
        for (int r = 0; r < kRelationCount; ++r) {
          SetIntrinsic(static_cast<Scheme>(s), static_cast<Nature>(n), static_cast<Orientation>(o), static_cast<Relation>(r), 0.5);
        }
      }
    }
  }
}

bool FramePrior::FramesCoincide(Nature nature, Orientation o, Relation relative) {
  return RelativeToIntrinsic(relative, nature, o) == relative;
}

void FramePrior::SetIntrinsic(Scheme s, Nature nature, Orientation o, Relation relative, double p_intrinsic) {
  p_[Index(s, Frame::kIntrinsic, nature, o, relative)] = p_intrinsic;
  p_[Index(s, Frame::kRelative, nature, o, relative)] = 1.0 - p_intrinsic;
}

CategoryTable LoadCategoryTable(std::string_view json_text) {
  const Json j = ParseJson(json_text, "the category table");
  if (!j.contains("categories") || !j["categories"].is_array()) Bad("the category table needs an array 'categories'", "categories");
  std::vector<Category> out;
  for (const Json& c : j["categories"]) {
    const std::string where = "categories[" + std::to_string(out.size()) + "]";
    if (!c.is_object() || !c.contains("id") || !c["id"].is_string()) Bad(where + " needs a string 'id'", where);
    for (const auto& [key, value] : c.items()) {
      if (key != "id" && key != "name" && key != "nature" && key != "words" && key != "front") {
        Bad(where + " has an unknown key '" + key + "'", where);
      }
    }
    Category cat;
    cat.id = c["id"].get<std::string>();
    cat.name = c.contains("name") && c["name"].is_string() ? c["name"].get<std::string>() : cat.id;
    const std::string nature = c.contains("nature") && c["nature"].is_string() ? c["nature"].get<std::string>() : "";
    if (nature == "vehicle") cat.nature = Nature::kVehicle;
    else if (nature == "opposite") cat.nature = Nature::kOpposite;
    else if (nature == "none") cat.nature = Nature::kNone;
    else Bad(where + " ('" + cat.id + "') needs nature vehicle, opposite or none", where + ".nature");
    if (c.contains("words")) {
      if (!c["words"].is_array()) Bad(where + ".words must be an array of strings", where + ".words");
      for (const Json& w : c["words"]) {
        if (!w.is_string()) Bad(where + ".words must be an array of strings", where + ".words");
        cat.words.push_back(w.get<std::string>());
      }
    }
    if (c.contains("front")) {
      const Json& f = c["front"];
      const std::string fw = where + ".front";
      if (!f.is_object()) Bad(fw + " must be an object {rule, weight, reach_m, towards}", fw);
      for (const auto& [key, value] : f.items()) {
        if (key != "rule" && key != "weight" && key != "reach_m" && key != "towards") Bad(fw + " has an unknown key '" + key + "'", fw);
      }
      const std::string rule = f.contains("rule") && f["rule"].is_string() ? f["rule"].get<std::string>() : "";
      if (rule == "back_to_wall") cat.front.rule = FrontRule::kBackToWall;
      else if (rule == "face_piece") cat.front.rule = FrontRule::kFacePiece;
      else if (rule == "face_room") cat.front.rule = FrontRule::kFaceRoom;
      else if (rule == "none") cat.front.rule = FrontRule::kNone;
      else Bad(fw + ".rule must be back_to_wall, face_piece, face_room or none", fw + ".rule");
      const auto number = [&](const char* key, double fallback, double lo, double hi) {
        if (!f.contains(key)) return fallback;
        if (!f[key].is_number() || !(f[key].get<double>() >= lo && f[key].get<double>() <= hi)) {
          Bad(fw + "." + key + " must be a number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]", fw + "." + key);
        }
        return f[key].get<double>();
      };
      cat.front.weight = number("weight", 0.0, 0.0, 1.0);
      cat.front.reach_m = number("reach_m", 0.6, 0.0, 10.0);
      if (f.contains("towards")) {
        if (!f["towards"].is_string()) Bad(fw + ".towards must be a category id", fw + ".towards");
        cat.front.towards = f["towards"].get<std::string>();
      }
      if (cat.front.rule == FrontRule::kFacePiece && cat.front.towards.empty()) Bad(fw + " (face_piece) needs 'towards'", fw + ".towards");
    }
    out.push_back(std::move(cat));
  }
  for (const Category& c : out) {
    if (c.front.rule != FrontRule::kFacePiece) continue;
    if (std::none_of(out.begin(), out.end(), [&](const Category& o) { return o.id == c.front.towards; })) {
      Bad("categories: '" + c.id + "' faces an unknown category '" + c.front.towards + "'", "categories");
    }
  }
  return CategoryTable(std::move(out));
}

FramePrior LoadFramePrior(std::string_view json_text) {
  const Json j = ParseJson(json_text, "the frame prior");
  if (!j.contains("schemes") || !j["schemes"].is_object()) Bad("the frame prior needs an object 'schemes'", "schemes");
  FramePrior prior;
  for (int s = 0; s < kSchemeCount; ++s) {
    const auto scheme = static_cast<Scheme>(s);
    const std::string sp = std::string("schemes.") + SchemeId(scheme);
    if (!j["schemes"].contains(SchemeId(scheme))) Bad("the frame prior lacks scheme '" + std::string(SchemeId(scheme)) + "'", sp);
    const Json& js = j["schemes"][SchemeId(scheme)];
    for (int n = 0; n < kNatureCount; ++n) {
      const auto nature = static_cast<Nature>(n);
      const std::string np = sp + "." + NatureId(nature);
      if (!js.is_object() || !js.contains(NatureId(nature)) || !js[NatureId(nature)].is_object()) Bad(np + " is missing", np);
      const Json& jn = js[NatureId(nature)];
      for (int o = 0; o < kOrientationCount; ++o) {
        const auto orient = static_cast<Orientation>(o);
        const std::string op = np + "." + OrientationId(orient);
        if (!jn.contains(OrientationId(orient)) || !jn[OrientationId(orient)].is_object()) Bad(op + " is missing", op);
        const Json& jo = jn[OrientationId(orient)];
        for (int r = 0; r < kRelationCount; ++r) {
          const auto rel = static_cast<Relation>(r);
          const std::string rp = op + "." + RelationId(rel);
          if (!jo.contains(RelationId(rel))) Bad(rp + " is missing", rp);
          const Json& v = jo[RelationId(rel)];
          if (!v.is_number() || !(v.get<double>() >= 0.0 && v.get<double>() <= 1.0)) Bad(rp + " must be P(intrinsic) in [0, 1]", rp);
          prior.SetIntrinsic(scheme, nature, orient, rel, v.get<double>());
        }
      }
    }
  }
  return prior;
}

Knowledge LoadKnowledge(std::string_view json_text) {
  const Json j = ParseJson(json_text, "the grounding knowledge");
  for (const auto& [key, value] : j.items()) {
    if (key != "categories" && key != "frame_prior") Bad("the grounding knowledge has an unknown key '" + key + "'", key);
  }
  Knowledge k = DefaultKnowledge();
  if (j.contains("categories")) k.categories = LoadCategoryTable(j["categories"].dump());
  if (j.contains("frame_prior")) k.prior = LoadFramePrior(j["frame_prior"].dump());
  return k;
}

std::string CompleteKnowledgeJson(std::string_view json_text) {
  if (json_text.empty()) {
    return Json{{"categories", Json::parse(DefaultCategoriesJson())}, {"frame_prior", Json::parse(DefaultFramePriorJson())}}.dump();
  }
  (void)LoadKnowledge(json_text);  // throws naming the bad entry
  Json doc = Json::parse(json_text);
  if (!doc.contains("categories")) doc["categories"] = Json::parse(DefaultCategoriesJson());
  if (!doc.contains("frame_prior")) doc["frame_prior"] = Json::parse(DefaultFramePriorJson());
  return doc.dump();
}

const Knowledge& DefaultKnowledge() {
  static const Knowledge kDefault{LoadCategoryTable(DefaultCategoriesJson()), LoadFramePrior(DefaultFramePriorJson())};
  return kDefault;
}

}  // namespace anchordb::engine::grounding
