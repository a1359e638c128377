#include "engine/grid/fusion.h"

#include "schema/error.h"

namespace anchordb::engine {

MaskGrid Threshold(const ProbabilityGrid& probability, double threshold) {
  MaskGrid mask(probability.geometry, 0);
  for (std::size_t i = 0; i < mask.cells.size(); ++i) mask.cells[i] = probability.cells[i] > threshold ? 1 : 0;
  return mask;
}

MaskGrid Fuse(FuseOp op, const std::vector<MaskGrid>& operands) {
  if (operands.size() < 2) throw Error(ErrorCode::kUnprocessable, "a fused layer needs at least two operands");
  for (const auto& m : operands) {
    if (!(m.geometry == operands.front().geometry)) {
      throw Error(ErrorCode::kUnprocessable, "fused operands must cover the same grid");
    }
  }
  MaskGrid out(operands.front().geometry, 0);
  for (std::size_t i = 0; i < out.cells.size(); ++i) {
    int count = 0;
    for (const auto& m : operands) count += m.cells[i];
    const int rest = count - operands.front().cells[i];
    bool v = false;
    switch (op) {
      case FuseOp::kAnd: v = count == static_cast<int>(operands.size()); break;
      case FuseOp::kOr: v = count > 0; break;
      case FuseOp::kAndNot: v = operands.front().cells[i] && rest == 0; break;
      case FuseOp::kXor: v = (count % 2) == 1; break;
    }
    out.cells[i] = v ? 1 : 0;
  }
  return out;
}

}  // namespace anchordb::engine
