#pragma once
// The stored form of a furniture graph's live n-best hypotheses (thesis 5.3.3): a versioned f64 array in a blob of
// storage/blob_codec.h. The records are storage's own (plain numbers); services/furniture/hypotheses_records.h maps
// them to and from the engine's grounding types, so storage/ needs no engine header.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace anchordb::storage {

// The sizes a stored hypothesis set must agree with: the graph it was grounded on (vertices, categories, directed
// edges) and the number of values each enumerated field may take.
struct HypothesesShape {
  int vertices = 0;
  int categories = 0;
  int directed_edges = 0;
  int relation_count = 0;
  int orientation_count = 0;
  int scheme_count = 0;
  int interpretation_count = 0;
};

struct StoredMatch {
  int directed_edge = 0;
  int interpretation = 0;
  int relation = 0;  // the relative relation the match read
  int scheme = 0;
  double score = 0.0;
  int located_category = -1;    // -1: not recorded (version 1)
  int reference_category = -1;
};

struct StoredHeldStep {
  int step = 0;
  int located = 0;
  int relation = 0;
  int reference = 0;
};

struct StoredHypothesis {
  std::int64_t id = 0;
  std::int64_t parent_id = -1;
  std::optional<int> scheme;
  double score = 0.0;
  std::vector<StoredMatch> matches;
  std::vector<std::int64_t> lineage;
  std::vector<int> lineage_ranks;
  std::vector<double> category;     // vertices x categories
  std::vector<double> orientation;  // vertices x orientation_count
  std::vector<double> relation;     // directed_edges x relation_count
};

struct StoredHypothesisSet {
  int step = 0;
  std::int64_t next_id = 1;
  std::vector<StoredHypothesis> ranked;
  std::vector<StoredHeldStep> held;
};

// Throws Error(kInvalidArgument) when `set` does not have `shape`'s sizes.
std::string EncodeHypotheses(const HypothesesShape& shape, const StoredHypothesisSet& set);
// Throws Error(kInternal) when the blob is corrupt or its shape does not match `shape`.
StoredHypothesisSet DecodeHypotheses(const HypothesesShape& shape, std::string_view blob);

}  // namespace anchordb::storage
