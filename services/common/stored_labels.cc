#include "services/common/stored_labels.h"

#include "schema/error.h"
#include "schema/json_io.h"

namespace anchordb::services {

std::optional<engine::LabelWeights> ReadLabelWeights(const std::string& stored) {
  const json::Json j = json::Json::parse(stored, nullptr, false);
  if (!j.is_object()) return std::nullopt;
  engine::LabelWeights out;
  for (const auto& [label, weight] : j.items()) {
    if (weight.is_number()) out[label] = weight.get<double>();
  }
  return out;
}

engine::LabelWeights DecodeLabelWeights(const std::string& stored, const std::string& what) {
  auto weights = ReadLabelWeights(stored);
  if (!weights) throw Error(ErrorCode::kInternal, what + ": the stored labels are not a JSON object");
  return std::move(*weights);
}

std::string EncodeLabelWeights(const engine::LabelWeights& weights) { return json::Json(weights).dump(); }

}  // namespace anchordb::services
