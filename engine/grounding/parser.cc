#include "engine/grounding/parser.h"

#include <algorithm>
#include <cctype>
#include <optional>
#include <set>
#include <vector>

#include "schema/error.h"

namespace anchordb::engine::grounding {
namespace {

constexpr const char* kRelationVocabulary = "left of, right of, in front of, behind";

const std::set<std::string>& Fillers() {
  static const std::set<std::string> kWords = {
      "the", "a", "an", "is", "are", "was", "stands", "stand", "standing", "sits", "sit", "sitting", "stood",
      "located", "placed", "situated", "positioned", "put", "there", "here", "it", "you", "can", "could", "see",
      "find", "will", "i", "we", "and", "also", "then", "now", "s", "one", "which", "that", "has", "been", "be",
      "please", "my", "our", "your", "this"};
  return kWords;
}

// Words that intensify a following relation ("right behind", "directly in front of").
const std::set<std::string>& Intensifiers() {
  static const std::set<std::string> kWords = {"right", "directly", "just", "straight", "exactly"};
  return kWords;
}

// Spatial words of relations this model does not know.
const std::set<std::string>& UnsupportedRelations() {
  static const std::set<std::string> kWords = {
      "next", "beside", "besides", "near", "nearby", "close", "under", "underneath", "beneath", "below", "above",
      "over", "on", "top", "between", "across", "opposite", "inside", "in", "into", "around", "by", "against",
      "along", "facing", "at", "with", "within", "outside", "beyond", "past", "towards", "toward"};
  return kWords;
}

std::vector<std::string> Tokenize(std::string_view text) {
  std::vector<std::string> tokens;
  std::string current;
  for (char c : text) {
    const unsigned char u = static_cast<unsigned char>(c);
    if (std::isalnum(u) || c == '_') {
      current += static_cast<char>(std::tolower(u));
    } else {
      if (!current.empty()) tokens.push_back(current);
      current.clear();
    }
  }
  if (!current.empty()) tokens.push_back(current);
  return tokens;
}

std::string Join(const std::vector<std::string>& t, std::size_t from, std::size_t to) {
  std::string out;
  for (std::size_t i = from; i < to; ++i) out += (i > from ? " " : "") + t[i];
  return out;
}

struct RelationMatch {
  Relation relation = Relation::kLeftOf;
  std::size_t length = 0;
};

// The relation phrase starting at token i, if any.
std::optional<RelationMatch> MatchRelation(const std::vector<std::string>& t, std::size_t i) {
  const auto at = [&](std::size_t j) -> const std::string& {
    static const std::string kEmpty;
    return j < t.size() ? t[j] : kEmpty;
  };
  if (at(i) == "behind") return RelationMatch{Relation::kBehind, 1};
  if (at(i) == "in" && at(i + 1) == "back" && at(i + 2) == "of") return RelationMatch{Relation::kBehind, 3};
  if (at(i) == "in") {
    std::size_t j = i + 1;
    if (at(j) == "the") ++j;
    if (at(j) == "front" && at(j + 1) == "of") return RelationMatch{Relation::kInFrontOf, j + 2 - i};
  }
  // [to|on|at|towards] [the] (left|right) [hand] [side] of
  std::size_t j = i;
  if (at(j) == "to" || at(j) == "on" || at(j) == "at" || at(j) == "towards" || at(j) == "toward") ++j;
  if (at(j) == "the") ++j;
  if (at(j) != "left" && at(j) != "right") return std::nullopt;
  const Relation r = at(j) == "left" ? Relation::kLeftOf : Relation::kRightOf;
  ++j;
  if (at(j) == "hand") ++j;
  if (at(j) == "side") ++j;
  if (at(j) != "of") return std::nullopt;
  return RelationMatch{r, j + 1 - i};
}

[[noreturn]] void NotUnderstood(const std::string& message, const std::string& field) {
  throw Error(ErrorCode::kUnprocessable, message, field);
}

std::string Quoted(const std::vector<std::string>& words) {
  std::string out;
  for (const std::string& w : words) out += (out.empty() ? "'" : ", '") + w + "'";
  return out;
}

}  // namespace

ParsedDescription ParseSentence(std::string_view text, const CategoryTable& categories, const std::string& field) {
  const std::vector<std::string> t = Tokenize(text);
  if (t.empty()) NotUnderstood("the sentence is empty", field);
  struct Item {
    bool is_relation = false;
    Relation relation = Relation::kLeftOf;
    int category = -1;
    std::string words;
  };
  std::vector<Item> items;
  std::vector<std::string> unknown, unsupported;
  const std::size_t max_tokens = static_cast<std::size_t>(categories.MaxWordTokens());
  for (std::size_t i = 0; i < t.size();) {
    if (auto m = MatchRelation(t, i)) {
      items.push_back({true, m->relation, -1, Join(t, i, i + m->length)});
      i += m->length;
      continue;
    }
    bool found = false;
    for (std::size_t len = std::min(max_tokens, t.size() - i); len >= 1 && !found; --len) {
      const std::string phrase = Join(t, i, i + len);
      const int c = categories.IndexOfWord(phrase);
      if (c >= 0) {
        items.push_back({false, Relation::kLeftOf, c, phrase});
        i += len;
        found = true;
      }
    }
    if (found) continue;
    if (Fillers().count(t[i]) || (Intensifiers().count(t[i]) && MatchRelation(t, i + 1))) {
      ++i;
      continue;
    }
    if (UnsupportedRelations().count(t[i])) {
      std::string phrase = t[i];
      if (i + 1 < t.size() && (t[i + 1] == "to" || t[i + 1] == "of")) phrase += " " + t[++i];
      unsupported.push_back(phrase);
    } else {
      unknown.push_back(t[i]);
    }
    ++i;
  }
  if (!unknown.empty()) {
    std::string also;
    if (!unsupported.empty()) also = "; the relation " + Quoted(unsupported) + " is not in the vocabulary either";
    NotUnderstood("not understood: " + Quoted(unknown) + " (furniture words are those of the categories " +
                      categories.IdList() + "; relations are " + kRelationVocabulary + ")" + also, field);
  }
  if (!unsupported.empty()) {
    NotUnderstood("the relation " + Quoted(unsupported) + " is not in the vocabulary (" + kRelationVocabulary + ")", field);
  }
  std::vector<const Item*> relations, furniture;
  for (const Item& item : items) (item.is_relation ? relations : furniture).push_back(&item);
  if (relations.empty()) {
    NotUnderstood("the sentence names no relation (" + std::string(kRelationVocabulary) + ")", field);
  }
  if (relations.size() > 1) NotUnderstood("the sentence names more than one relation: '" + relations[0]->words + "', '" + relations[1]->words + "'", field);
  if (furniture.size() != 2) {
    NotUnderstood("the sentence must name two pieces of furniture, it names " + std::to_string(furniture.size()), field);
  }
  ParsedDescription out;
  out.relation_words = relations[0]->words;
  out.description.relation = relations[0]->relation;
  const auto position = [&](const Item* p) { return p - items.data(); };
  const auto rel = position(relations[0]), first = position(furniture[0]), second = position(furniture[1]);
  const Item* located = nullptr;
  const Item* reference = nullptr;
  if (first < rel && rel < second) {  // the table is in front of the shelf
    located = furniture[0], reference = furniture[1];
  } else if (rel < first) {           // left of the sofa is the plant
    reference = furniture[0], located = furniture[1];
  } else {
    NotUnderstood("the sentence does not parse: expected '<furniture> is <relation> <furniture>' or "
                  "'<relation> <furniture> is <furniture>'", field);
  }
  out.description.located = located->category;
  out.description.reference = reference->category;
  out.located_words = located->words;
  out.reference_words = reference->words;
  return out;
}

Relation ParseRelation(std::string_view text, const std::string& field) {
  std::string id(text);
  for (char& c : id) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (int r = 0; r < kRelationCount; ++r) {
    if (id == RelationId(static_cast<Relation>(r))) return static_cast<Relation>(r);
  }
  std::vector<std::string> t = Tokenize(text);
  // "left_of" style ids of unknown relations arrive as one token with underscores.
  if (t.size() == 1 && t[0].find('_') != std::string::npos) {
    std::string spaced = t[0];
    std::replace(spaced.begin(), spaced.end(), '_', ' ');
    t = Tokenize(spaced);
  }
  std::size_t i = 0;
  while (i < t.size() && Intensifiers().count(t[i]) && MatchRelation(t, i + 1)) ++i;
  if (auto m = MatchRelation(t, i); m && i + m->length == t.size()) return m->relation;
  NotUnderstood("the relation '" + std::string(text) + "' is not in the vocabulary (left_of, right_of, in_front_of, behind)", field);
}

int ParseCategory(std::string_view text, const CategoryTable& categories, const std::string& field) {
  const int c = categories.IndexOfWord(Join(Tokenize(text), 0, Tokenize(text).size()));
  if (c >= 0) return c;
  const int by_id = categories.IndexOfId(text);
  if (by_id >= 0) return by_id;
  NotUnderstood("unknown furniture word '" + std::string(text) + "' (known categories: " + categories.IdList() + ")", field);
}

}  // namespace anchordb::engine::grounding
