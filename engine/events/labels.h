#pragma once
// Labels of instances (thesis 3.3.4 "Lost key"; SPEC §4.4): what people call an object, from dialog or an operator.
// An instance keeps a weight per label; dialog adds evidence, an operator replaces it. Answers use the normalised
// distribution.
#include <cstddef>
#include <map>
#include <string>
#include <string_view>

namespace anchordb::engine {

// Label -> accumulated weight (>= 0). Empty: the instance was never named.
using LabelWeights = std::map<std::string, double>;

// Lowercase, trimmed, inner whitespace collapsed to one space. Throws Error(kInvalidArgument) on control characters,
// Error(kUnprocessable) when the result is empty or longer than max_length; `field` names the request field.
std::string NormaliseLabel(std::string_view raw, std::size_t max_length, const std::string& field);

// The weights scaled to sum 1 (every label 0 when the weights sum to 0).
LabelWeights LabelDistribution(const LabelWeights& weights);
// p(label) under LabelDistribution; 0 for a label the instance never had.
double LabelProbability(const LabelWeights& weights, const std::string& label);
// The label of greatest weight (the first in alphabetical order among equals); empty when there is none.
std::string TopLabel(const LabelWeights& weights);
// The name a furniture piece goes by in a where-is placement: its most probable label (TopLabel; a perceived piece
// carries its whole p(f), an operator's piece one label), "furniture" when it has none.
std::string FurnitureName(const LabelWeights& names);
// A label from dialog adds one to its weight; an operator's label replaces all others (weight 1).
LabelWeights AddLabel(LabelWeights weights, const std::string& label, bool from_operator);

}  // namespace anchordb::engine
