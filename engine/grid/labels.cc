#include "engine/grid/labels.h"

#include <algorithm>

#include "schema/error.h"

namespace anchordb::engine {

LabelIdChoice ChooseLabelId(const std::map<int, std::string>& labels, const std::string& name) {
  int id = 0, max_id = 0;
  for (const auto& [key, label] : labels) {
    max_id = std::max(max_id, key);
    if (label == name && (id == 0 || std::to_string(key) > std::to_string(id))) id = key;
  }
  if (id != 0) return {id, false};
  if (max_id >= 65535) throw Error(ErrorCode::kUnprocessable, "label layer holds 65535 labels already", "label");
  return {max_id + 1, true};
}

void PaintMask(const MaskGrid& mask, std::uint16_t id, LabelGrid& labels) {
  for (std::size_t i = 0; i < mask.cells.size(); ++i) {
    if (mask.cells[i]) labels.cells[i] = id;
  }
}

}  // namespace anchordb::engine
