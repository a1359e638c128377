#pragma once
// A furniture graph's hypotheses in and out of their stored form: the engine's grounding types mapped to storage's
// records (storage/hypotheses_codec.h), with the graph's sizes as the shape the blob is checked against.
#include <string>
#include <string_view>

#include "engine/grounding/grounding.h"

namespace anchordb::services {

std::string EncodeHypotheses(const engine::grounding::FurnitureGraph& graph, const engine::grounding::HypothesisSet& set);
// Throws Error(kInternal) when the blob is corrupt or was stored for a graph of another shape.
engine::grounding::HypothesisSet DecodeHypotheses(const engine::grounding::FurnitureGraph& graph, std::string_view blob);

}  // namespace anchordb::services
