#pragma once
// The labels of an instance as its row stores them -- a JSON object {"label": weight, ...}, the text that the
// instance_labels index of migration 0005 reads on both engines -- and a classification's distribution, stored in
// the same form. One codec for every capability that reads or writes them (events, classification, furniture,
// segmentation); the header has no JSON (issue 30).
#include <optional>
#include <string>

#include "engine/events/labels.h"

namespace anchordb::services {

// nullopt when `stored` is not a JSON object; entries whose weight is not a number are left out.
std::optional<engine::LabelWeights> ReadLabelWeights(const std::string& stored);

// As ReadLabelWeights, but text that is not an object is Error(kInternal) naming `what` (the row it came from).
engine::LabelWeights DecodeLabelWeights(const std::string& stored, const std::string& what);

std::string EncodeLabelWeights(const engine::LabelWeights& weights);

}  // namespace anchordb::services
