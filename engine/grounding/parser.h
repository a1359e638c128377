#pragma once
// A small English reader for spatial descriptions of furniture (thesis 5.3.5: "located object -> spatial relation
// -> reference object", also in the other order). Accepted shapes, with any of a few filler words (the, a, is,
// stands, there, you can see, ...) in between:
//   "<located> is <relation> <reference>"     the table is in front of the shelf
//   "<relation> <reference> is <located>"     left of the sofa is the plant; in front of the shelf you can see the chair
// Furniture words come from the CategoryTable (synonyms and multi-word names such as "chest of drawers");
// relations are left of / right of (optionally "to the", "on the", "... side of"), in front of, behind,
// in back of. Everything else is refused with Error(kUnprocessable) naming the words that were not understood
// (field = the JSON field the text came from).
#include <string>
#include <string_view>

#include "engine/grounding/grounding.h"

namespace anchordb::engine::grounding {

struct ParsedDescription {
  Description description;
  std::string located_words;    // as spoken, e.g. "couch"
  std::string relation_words;   // e.g. "to the left of"
  std::string reference_words;
};

ParsedDescription ParseSentence(std::string_view text, const CategoryTable& categories, const std::string& field = "text");

// A relation given on its own: an id ("left_of", "in_front_of") or a phrase ("to the left of", "behind").
Relation ParseRelation(std::string_view text, const std::string& field = "relation");

// A furniture word or category id; Error(kUnprocessable) naming the word and the known categories otherwise.
int ParseCategory(std::string_view text, const CategoryTable& categories, const std::string& field);

}  // namespace anchordb::engine::grounding
