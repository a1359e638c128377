// Iterative walks over the OctoMap node streams (see the header): no liboctomap, no recursion.
#include "engine/octomap/octree_stream_check.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "schema/error.h"

namespace anchordb::engine {

namespace {

constexpr int kTreeDepth = 16;     // OcTree keys are 16 bits per axis: leaves lie at depth 16
constexpr std::size_t kOtNodeBytes = 5;  // float log-odds + child mask
constexpr std::size_t kBtNodeBytes = 2;  // 2 bits for each of 8 children

[[noreturn]] void Refuse(const std::string& what, const std::string& message) {
  throw Error(ErrorCode::kInvalidArgument, what + ": " + message, "body");
}

// Walks a tree stored depth-first (a node's record, then its children's subtrees in child order): `children(at)` is
// the number of child records that follow the record at offset `at`. Every record must lie inside the body, and only
// records down to `deepest_parent` may have child records (the root is at depth 0).
template <typename ChildRecords>
void WalkDepthFirst(std::string_view bytes, std::size_t at, std::size_t node_bytes, int deepest_parent,
                    const std::string& what, ChildRecords children) {
  // pending[d]: how many children of the current node at depth d are still to be read.
  std::vector<int> pending;
  pending.reserve(kTreeDepth + 1);
  int depth = 0;
  for (;;) {
    if (at + node_bytes > bytes.size()) Refuse(what, "truncated: a node lies past the end of the body");
    const int count = children(at);
    at += node_bytes;
    if (count > 0) {
      if (depth > deepest_parent) Refuse(what, "corrupt: the tree is deeper than 16 levels");
      pending.push_back(count);
      ++depth;
      continue;  // the first child follows
    }
    // A leaf: climb to the nearest ancestor with a child still to read.
    while (!pending.empty() && --pending.back() == 0) {
      pending.pop_back();
      --depth;
    }
    if (pending.empty()) return;
  }
}

int PopCount(std::uint8_t mask) {
  int n = 0;
  for (; mask != 0; mask &= static_cast<std::uint8_t>(mask - 1)) ++n;
  return n;
}

}  // namespace

void CheckOtNodeStream(std::string_view node_bytes) {
  // Every node has a record, the leaves at depth 16 too: parents down to depth 15.
  WalkDepthFirst(node_bytes, 0, kOtNodeBytes, kTreeDepth - 1, ".ot file", [&](std::size_t at) {
    return PopCount(static_cast<std::uint8_t>(node_bytes[at + 4]));
  });
}

void CheckBtNodeStream(std::string_view node_bytes) {
  // Per child two bits: 01 free leaf, 10 occupied leaf, 11 inner node (its own two bytes follow, in child order).
  // Only inner nodes have records, and the children of a depth-15 node are leaves: parents down to depth 14.
  WalkDepthFirst(node_bytes, 0, kBtNodeBytes, kTreeDepth - 2, ".bt file", [&](std::size_t at) {
    int inner = 0;
    for (int b = 0; b < 2; ++b) {
      const auto mask = static_cast<std::uint8_t>(node_bytes[at + static_cast<std::size_t>(b)]);
      for (int i = 0; i < 4; ++i) inner += ((mask >> (2 * i)) & 3u) == 3u ? 1 : 0;
    }
    return inner;
  });
}

}  // namespace anchordb::engine
