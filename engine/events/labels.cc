#include "engine/events/labels.h"

#include <cctype>

#include "schema/error.h"

namespace anchordb::engine {

std::string NormaliseLabel(std::string_view raw, std::size_t max_length, const std::string& field) {
  std::string out;
  bool space = false;
  for (unsigned char ch : raw) {
    if (std::isspace(ch)) {
      space = !out.empty();
      continue;
    }
    if (ch < 0x20) throw Error(ErrorCode::kInvalidArgument, "labels must not contain control characters", field);
    if (space) out.push_back(' '), space = false;
    out.push_back(static_cast<char>(std::tolower(ch)));
  }
  if (out.empty()) throw Error(ErrorCode::kUnprocessable, "label must not be empty", field);
  if (out.size() > max_length) throw Error(ErrorCode::kUnprocessable, "label is longer than " + std::to_string(max_length) + " characters", field);
  return out;
}

LabelWeights LabelDistribution(const LabelWeights& weights) {
  double sum = 0;
  for (const auto& [label, w] : weights) sum += w;
  LabelWeights out;
  for (const auto& [label, w] : weights) out[label] = sum > 0 ? w / sum : 0.0;
  return out;
}

double LabelProbability(const LabelWeights& weights, const std::string& label) {
  const LabelWeights d = LabelDistribution(weights);
  const auto it = d.find(label);
  return it == d.end() ? 0.0 : it->second;
}

std::string TopLabel(const LabelWeights& weights) {
  std::string top;
  double top_w = -1;
  for (const auto& [label, w] : weights) if (w > top_w) top_w = w, top = label;
  return top;
}

std::string FurnitureName(const LabelWeights& names) {
  const std::string top = TopLabel(names);
  return top.empty() ? "furniture" : top;
}

LabelWeights AddLabel(LabelWeights weights, const std::string& label, bool from_operator) {
  if (from_operator) return {{label, 1.0}};
  weights[label] += 1.0;
  return weights;
}

}  // namespace anchordb::engine
