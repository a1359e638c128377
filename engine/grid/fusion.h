#pragma once
// Fused layers (thesis 3.4.2): a logical operator over layers thresholded to booleans.
#include <vector>

#include "engine/grid/grid.h"

namespace anchordb::engine {

// True cells of `probability` (value strictly above threshold, so never-observed cells at 0.5 are false at 0.5).
MaskGrid Threshold(const ProbabilityGrid& probability, double threshold);

// and: all true; or: any true; and_not: first true and none of the others; xor: an odd number true.
// All operands must share one geometry (kUnprocessable otherwise); at least two operands.
MaskGrid Fuse(FuseOp op, const std::vector<MaskGrid>& operands);

}  // namespace anchordb::engine
