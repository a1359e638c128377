// The stored form of a furniture graph's live n-best hypotheses (a versioned f64 blob).
#include "storage/hypotheses_codec.h"

#include <cmath>
#include <cstring>

#include "schema/error.h"
#include "storage/blob_codec.h"

namespace anchordb::storage {

// ---- the hypotheses codec: f64 array
//   header: magic 4.5e6 + version (1 or 2), step, next_id, count, vertices, categories, directed edges
//   version 2 only: held steps h, then h x (step, located, relation, reference); each match also carries
//   (located_category, reference_category)
//   per hypothesis: id, parent_id, has_scheme, scheme, score, t; t x (directed, interpretation, relation, scheme,
//   score); t lineage ids; t lineage ranks; p(f) V x K; p(o) V x 4; p(r) D x 4
namespace {
constexpr double kCodecMagicV1 = 4'500'001.0;
constexpr double kCodecMagic = 4'500'002.0;

void CheckShape(const HypothesesShape& shape, const StoredHypothesisSet& set) {
  const auto bad = [](const std::string& what) {
    return Error(ErrorCode::kInvalidArgument, "hypotheses to store do not fit their graph: " + what);
  };
  const auto sized = [](const std::vector<double>& v, int a, int b) {
    return v.size() == static_cast<std::size_t>(a) * static_cast<std::size_t>(b);
  };
  for (const StoredHypothesis& h : set.ranked) {
    if (!sized(h.category, shape.vertices, shape.categories) || !sized(h.orientation, shape.vertices, shape.orientation_count) ||
        !sized(h.relation, shape.directed_edges, shape.relation_count)) {
      throw bad("a state's size");
    }
    if (h.lineage.size() != h.matches.size() || h.lineage_ranks.size() != h.matches.size()) throw bad("a lineage's length");
  }
}
}  // namespace

std::string EncodeHypotheses(const HypothesesShape& shape, const StoredHypothesisSet& set) {
  CheckShape(shape, set);
  std::vector<double> v = {kCodecMagic, static_cast<double>(set.step), static_cast<double>(set.next_id),
                           static_cast<double>(set.ranked.size()), static_cast<double>(shape.vertices),
                           static_cast<double>(shape.categories), static_cast<double>(shape.directed_edges),
                           static_cast<double>(set.held.size())};
  for (const StoredHeldStep& held : set.held) {
    v.insert(v.end(), {static_cast<double>(held.step), static_cast<double>(held.located),
                       static_cast<double>(held.relation), static_cast<double>(held.reference)});
  }
  for (const StoredHypothesis& h : set.ranked) {
    v.insert(v.end(), {static_cast<double>(h.id), static_cast<double>(h.parent_id), h.scheme ? 1.0 : 0.0,
                       h.scheme ? static_cast<double>(*h.scheme) : 0.0, h.score, static_cast<double>(h.matches.size())});
    for (const StoredMatch& m : h.matches) {
      v.insert(v.end(), {static_cast<double>(m.directed_edge), static_cast<double>(m.interpretation), static_cast<double>(m.relation),
                         static_cast<double>(m.scheme), m.score, static_cast<double>(m.located_category),
                         static_cast<double>(m.reference_category)});
    }
    for (std::int64_t id : h.lineage) v.push_back(static_cast<double>(id));
    for (int r : h.lineage_ranks) v.push_back(static_cast<double>(r));
    v.insert(v.end(), h.category.begin(), h.category.end());
    v.insert(v.end(), h.orientation.begin(), h.orientation.end());
    v.insert(v.end(), h.relation.begin(), h.relation.end());
  }
  return EncodeBlob(BlobElement::kF64, {static_cast<std::uint32_t>(v.size())}, AsBytes(v));
}

StoredHypothesisSet DecodeHypotheses(const HypothesesShape& shape, std::string_view blob) {
  const DecodedBlob d = DecodeBlob(blob);
  const auto corrupt = [](const std::string& what) {
    return Error(ErrorCode::kInternal, "stored furniture-graph hypotheses are corrupt: " + what);
  };
  if (d.element != BlobElement::kF64 || d.bytes.size() % sizeof(double) != 0) throw corrupt("not an f64 array");
  std::vector<double> v(d.bytes.size() / sizeof(double));
  std::memcpy(v.data(), d.bytes.data(), d.bytes.size());
  std::size_t at = 0;
  const auto next = [&]() {
    if (at >= v.size()) throw corrupt("truncated");
    return v[at++];
  };
  const auto next_int = [&](double lo, double hi) {
    const double x = next();
    if (!(x >= lo && x <= hi) || x != std::floor(x)) throw corrupt("a count or index is out of range");
    return static_cast<std::int64_t>(x);
  };
  const double magic = next();
  if (magic != kCodecMagic && magic != kCodecMagicV1) throw corrupt("unknown format");
  StoredHypothesisSet set;
  set.step = static_cast<int>(next_int(0, 1e9));
  set.next_id = next_int(0, 9e15);
  const std::int64_t count = next_int(1, 1e7);
  const std::size_t vertices = static_cast<std::size_t>(shape.vertices), k = static_cast<std::size_t>(shape.categories);
  const int directed = shape.directed_edges;
  if (next_int(0, 1e9) != shape.vertices || next_int(0, 1e9) != shape.categories || next_int(0, 1e9) != directed) {
    throw corrupt("shape does not match the graph");
  }
  if (magic == kCodecMagic) {
    const std::int64_t held = next_int(0, set.step);
    for (std::int64_t i = 0; i < held; ++i) {
      StoredHeldStep h;
      h.step = static_cast<int>(next_int(0, set.step - 1));
      h.located = static_cast<int>(next_int(0, shape.categories - 1));
      h.relation = static_cast<int>(next_int(0, shape.relation_count - 1));
      h.reference = static_cast<int>(next_int(0, shape.categories - 1));
      set.held.push_back(h);
    }
  }
  for (std::int64_t i = 0; i < count; ++i) {
    StoredHypothesis h;
    h.id = next_int(0, 9e15);
    h.parent_id = next_int(-1, 9e15);
    const bool has_scheme = next_int(0, 1) == 1;
    const int scheme = static_cast<int>(next_int(0, shape.scheme_count - 1));
    if (has_scheme) h.scheme = scheme;
    h.score = next();
    const std::int64_t t = next_int(0, set.step);
    for (std::int64_t s = 0; s < t; ++s) {
      StoredMatch m;
      m.directed_edge = static_cast<int>(next_int(0, directed - 1));
      m.interpretation = static_cast<int>(next_int(0, shape.interpretation_count - 1));
      m.relation = static_cast<int>(next_int(0, shape.relation_count - 1));
      m.scheme = static_cast<int>(next_int(0, shape.scheme_count - 1));
      m.score = next();
      if (magic == kCodecMagic) {
        m.located_category = static_cast<int>(next_int(-1, shape.categories - 1));
        m.reference_category = static_cast<int>(next_int(-1, shape.categories - 1));
      }
      h.matches.push_back(m);
    }
    for (std::int64_t s = 0; s < t; ++s) h.lineage.push_back(next_int(0, 9e15));
    for (std::int64_t s = 0; s < t; ++s) h.lineage_ranks.push_back(static_cast<int>(next_int(0, 1e7)));
    const auto take = [&](std::vector<double>& out, std::size_t n) {
      if (at + n > v.size()) throw corrupt("truncated");
      out.assign(v.begin() + static_cast<std::ptrdiff_t>(at), v.begin() + static_cast<std::ptrdiff_t>(at + n));
      at += n;
    };
    take(h.category, vertices * k);
    take(h.orientation, vertices * static_cast<std::size_t>(shape.orientation_count));
    take(h.relation, static_cast<std::size_t>(directed) * static_cast<std::size_t>(shape.relation_count));
    set.ranked.push_back(std::move(h));
  }
  if (at != v.size()) throw corrupt("trailing data");
  return set;
}

}  // namespace anchordb::storage
