// The keyframe analysis queue's rows (storage/analysis_queue.h) on both engines: each map's head comes with the
// number of the map's rows not given up, PendingAnalyses counts the same, and a given-up row neither heads nor counts.
#include "storage/analysis_queue.h"

#include <gtest/gtest.h>

#include "storage/repositories.h"
#include "storage/scene_repository.h"
#include "tests/support/pg_scratch.h"
#include "tests/support/test_store.h"

namespace anchordb::storage {
namespace analysis_queue_rows_test {

class AnalysisQueueRowsTest : public ::testing::TestWithParam<Engine> {
 protected:
  testing::TestDatabase db_{GetParam()};
};
INSTANTIATE_TEST_SUITE_P(Engines, AnalysisQueueRowsTest, testing::BothEngines(), testing::EngineName);

TEST_P(AnalysisQueueRowsTest, HeadsCarryTheirMapsPendingCountAndGivenUpRowsAreLeftOut) {
  const auto store = testing::OpenStoreWithMaps(db_.location(), {"a", "b"});
  std::vector<std::int64_t> a_rows, b_rows;
  store->Write([&](Connection& c) {
    const auto queue = [&](const std::string& map, std::int64_t scene, std::vector<std::int64_t>& ids) {
      KeyframeRecord k;
      k.map_id = map;
      k.scene_id = scene;
      k.kind = "manual";
      k.depth = k.background = "x";
      const std::int64_t id = InsertKeyframe(c, k);
      EnqueueAnalysis(c, {id, map, scene, 100 + id});
      ids.push_back(id);
    };
    SceneRecord a, b;
    a.map_id = "a";
    b.map_id = "b";
    const std::int64_t sa = InsertScene(c, a), sb = InsertScene(c, b);
    for (int i = 0; i < 3; ++i) queue("a", sa, a_rows);
    queue("b", sb, b_rows);
  });
  store->Write([&](Connection& c) { RecordAnalysisFailure(c, a_rows[0], "broken", 0, true); });  // given up

  const std::vector<QueueHead> heads = store->Read([](Connection& c) { return QueueHeads(c); });
  ASSERT_EQ(heads.size(), 2u);
  EXPECT_EQ(heads[0].row.keyframe_id, a_rows[1]) << "the given-up row is no head";
  EXPECT_EQ(heads[0].row.map_id, "a");
  EXPECT_EQ(heads[0].map_pending, 2);
  EXPECT_EQ(heads[1].row.keyframe_id, b_rows[0]);
  EXPECT_EQ(heads[1].map_pending, 1);
  EXPECT_EQ(store->Read([](Connection& c) { return PendingAnalyses(c, "a"); }), 2);
  EXPECT_EQ(store->Read([](Connection& c) { return PendingAnalyses(c, "b"); }), 1);
  EXPECT_EQ(store->Read([](Connection& c) { return PendingAnalyses(c, "nowhere"); }), 0);
  store->Write([&](Connection& c) { EXPECT_TRUE(DequeueAnalysis(c, a_rows[1])); });
  EXPECT_EQ(store->Read([](Connection& c) { return QueueHeads(c); })[0].map_pending, 1);
}

}  // namespace
}  // namespace anchordb::storage
