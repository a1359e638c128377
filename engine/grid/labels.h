#pragma once
// Label ids of a label layer: each label name has one id in 1..65535; cells hold ids (0 = no label).
#include <cstdint>
#include <map>
#include <string>

#include "engine/grid/grid.h"

namespace anchordb::engine {

struct LabelIdChoice {
  int id = 0;
  bool is_new = false;  // `name` was not in the table; the caller adds (id, name)
};

// The id painting `name` uses: the id the table already gives that name (of several, the one whose decimal text
// sorts last, as the stored table is ordered), else one above the highest id in use.
// Throws Error(kUnprocessable, field "label") when a new id would exceed 65535.
LabelIdChoice ChooseLabelId(const std::map<int, std::string>& labels, const std::string& name);

// Writes `id` into every cell of `labels` whose cell in `mask` (same geometry) is set.
void PaintMask(const MaskGrid& mask, std::uint16_t id, LabelGrid& labels);

}  // namespace anchordb::engine
