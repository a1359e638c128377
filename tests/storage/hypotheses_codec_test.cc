// The stored form of a furniture graph's hypotheses (storage/hypotheses_codec.h, reached through the service's mapping
// of the engine's types): a round trip keeps every hypothesis; a blob of another graph's shape or a corrupted one is
// refused, and so are records that do not fit the shape they are stored for.
#include "services/furniture/hypotheses_records.h"
#include "storage/hypotheses_codec.h"

#include <gtest/gtest.h>

#include "schema/error.h"

namespace anchordb::services {
namespace hypotheses_codec_test {

namespace g = engine::grounding;

TEST(HypothesesCodec, RoundTripsAndRejectsCorruption) {
  const g::Knowledge& k = g::DefaultKnowledge();
  const std::vector<double> pf(10, 0.1);
  const g::FurnitureGraph graph = g::BuildFurnitureGraph(
      {{0, 0}, 0}, {{"a", {2, 0}, {0.5, 0.5}, 0, pf}, {"b", {2, 1}, {0.5, 0.5}, 0, pf}, {"c", {3, 0}, {0.5, 0.5}, 0, pf}}, 10, {});
  g::GroundingParams params;
  params.n_best = 7;
  g::HypothesisSet set = g::InitialHypotheses(graph);
  set = g::Ground(graph, k, set, {0, g::Relation::kLeftOf, 1}, params);
  set = g::Ground(graph, k, set, {2, g::Relation::kBehind, 0}, params);
  const g::HypothesisSet back = DecodeHypotheses(graph, EncodeHypotheses(graph, set));
  ASSERT_EQ(back.ranked.size(), set.ranked.size());
  EXPECT_EQ(back.step, 2);
  EXPECT_EQ(back.next_id, set.next_id);
  for (std::size_t i = 0; i < set.ranked.size(); ++i) {
    EXPECT_EQ(back.ranked[i].id, set.ranked[i].id);
    EXPECT_EQ(back.ranked[i].score, set.ranked[i].score);
    EXPECT_EQ(back.ranked[i].scheme, set.ranked[i].scheme);
    EXPECT_EQ(back.ranked[i].state, set.ranked[i].state);
    EXPECT_EQ(back.ranked[i].lineage_ranks, set.ranked[i].lineage_ranks);
  }
  const g::FurnitureGraph other = g::BuildFurnitureGraph({{0, 0}, 0}, {{"a", {2, 0}, {0.5, 0.5}, 0, pf}, {"b", {2, 1}, {0.5, 0.5}, 0, pf}}, 10, {});
  EXPECT_THROW(DecodeHypotheses(other, EncodeHypotheses(graph, set)), Error);
  std::string blob = EncodeHypotheses(graph, set);
  blob[blob.size() / 2] ^= 0x5a;
  EXPECT_THROW(DecodeHypotheses(graph, blob), Error);
  EXPECT_THROW(DecodeHypotheses(graph, ""), Error);
}

TEST(HypothesesCodec, HeldStepsAndDescribedCategoriesRoundTrip) {
  const std::vector<double> pf(10, 0.1);
  const g::FurnitureGraph graph = g::BuildFurnitureGraph(
      {{0, 0}, 0}, {{"a", {2, 0}, {0.5, 0.5}, 0, pf}, {"b", {2, 1}, {0.5, 0.5}, 0, pf}, {"c", {3, 0}, {0.5, 0.5}, 0, pf}}, 10, {});
  const g::GroundingParams params;
  g::HypothesisSet set = g::Ground(graph, g::DefaultKnowledge(), g::InitialHypotheses(graph), {0, g::Relation::kLeftOf, 1}, params);
  set.held.push_back({0, {0, g::Relation::kLeftOf, 1}});  // as an ambiguous step leaves it
  const g::HypothesisSet back = DecodeHypotheses(graph, EncodeHypotheses(graph, set));
  ASSERT_EQ(back.held.size(), 1u);
  EXPECT_EQ(back.held[0].step, 0);
  EXPECT_EQ(back.held[0].description.located, 0);
  EXPECT_EQ(back.held[0].description.relation, g::Relation::kLeftOf);
  EXPECT_EQ(back.held[0].description.reference, 1);
  ASSERT_EQ(back.ranked.size(), set.ranked.size());
  for (const g::Hypothesis& h : back.ranked) {
    EXPECT_EQ(h.matches[0].located_category, 0);
    EXPECT_EQ(h.matches[0].reference_category, 1);
  }
}

TEST(HypothesesCodec, RecordsThatDoNotFitTheirShapeAreRefused) {
  const storage::HypothesesShape shape{2, 3, 2, 4, 4, 4, 5};
  storage::StoredHypothesisSet set;
  storage::StoredHypothesis& h = set.ranked.emplace_back();
  h.category.assign(6, 1.0 / 3);
  h.orientation.assign(8, 0.25);
  h.relation.assign(8, 0.25);
  const storage::StoredHypothesisSet back = storage::DecodeHypotheses(shape, storage::EncodeHypotheses(shape, set));
  ASSERT_EQ(back.ranked.size(), 1u);
  EXPECT_EQ(back.ranked[0].category, h.category);
  EXPECT_FALSE(back.ranked[0].scheme.has_value());
  h.relation.pop_back();
  try {
    storage::EncodeHypotheses(shape, set);
    ADD_FAILURE() << "a state of the wrong size was encoded";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
  }
  h.relation.push_back(0.25);
  h.lineage.push_back(0);  // a lineage without its match
  EXPECT_THROW(storage::EncodeHypotheses(shape, set), Error);
}

}  // namespace
}  // namespace anchordb::services
