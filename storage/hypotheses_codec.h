#pragma once
// The stored form of a furniture graph's live n-best hypotheses (thesis 5.3.3): a versioned f64 array in a blob of
// storage/blob_codec.h. Only the engine's grounding types are needed (header-only use: no link to the engine).
#include <string>
#include <string_view>

#include "engine/grounding/grounding.h"

namespace anchordb::storage {

std::string EncodeHypotheses(const engine::grounding::FurnitureGraph& graph, const engine::grounding::HypothesisSet& set);
// Throws Error(kInternal) when the blob is corrupt or its shape does not match `graph`.
engine::grounding::HypothesisSet DecodeHypotheses(const engine::grounding::FurnitureGraph& graph, std::string_view blob);

}  // namespace anchordb::storage
