// Forgetting (storage/forgetting.h) on a real SQLite file: what goes, what a live reference keeps, dry runs and
// aborted runs change nothing, no dangling reference afterwards. (The request: tests/api/job_json_test.cc; incremental
// vacuum: forgetting_vacuum_test.cc; the job service around forgetting: tests/services/job_service_test.cc.)
// Suite names are lower case so that `ctest -R forget` selects them.
#include "storage/forgetting.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "schema/error.h"
#include "tests/storage/forgetting_fixture.h"

namespace anchordb::storage {
namespace forgetting_test {

using namespace forget_test;  // NOLINT: the fixture and its helpers are this file's vocabulary

// The scenario of most tests: every rule of forgetting, each with a row it removes and a row it must keep.
class forgetting : public ForgetFixture {
 protected:
  void SetUp() override {
    ForgetFixture::SetUp();
    const std::int64_t old_kf = kNow - 10 * kDay, old_event = kNow - 40 * kDay;
    scene_b = Scene("closed", kNow - 20 * kDay, std::nullopt);
    scene_a = Scene("superseded", kNow - 50 * kDay, scene_b);   // state dropped; row kept (its keyframe ka2 is evidence)
    scene_c = Scene("superseded", kNow - 50 * kDay, scene_b);   // no keyframes: state dropped and row deleted
    scene_d = Scene("observing", std::nullopt, std::nullopt, 3000, kNow - 1 * kDay);  // still observing: keyframes stay
    scene_f = Scene("observing", std::nullopt, std::nullopt, 3000, kNow - 30 * kDay);  // left open: abandoned
    scene_e = Scene("superseded", kNow - 50 * kDay, std::nullopt);  // superseder unknown: kept whole
    ka1 = Keyframe(scene_a, old_kf);
    ka2 = Keyframe(scene_a, old_kf);
    kb_pinned = Keyframe(scene_b, old_kf, true);
    kb_relevant = Keyframe(scene_b, old_kf, false, 0.8);
    kb_irrelevant = Keyframe(scene_b, old_kf, false, 0.3);
    kb_recent = Keyframe(scene_b, kNow - 1 * kDay);
    kb_segment = Keyframe(scene_b, old_kf);
    kb_event_segment = Keyframe(scene_b, old_kf);
    kb_event_evidence = Keyframe(scene_b, old_kf);
    kb_latest_segment = Keyframe(scene_b, old_kf);
    kd = Keyframe(scene_d, old_kf);
    kf = Keyframe(scene_f, old_kf);
    s_free = Segment(kb_segment);
    s_old_event = Segment(kb_event_segment);
    s_latest = Segment(kb_latest_segment);
    i1 = Instance(false);
    i2 = Instance(true);
    e_old = Event("removed", old_event, i1, s_old_event, {{kb_event_evidence, "before"}});
    e_latest = Event("added", kNow - 35 * kDay, i1, s_latest, {{ka2, "after"}});
    e_pinned_instance = Event("added", old_event, i2, std::nullopt, {});
    e_pinned = Event("added", old_event, std::nullopt, std::nullopt, {}, true);
    // A label of i1 newer than its latest position event: kept as a label, and not the event that proves i1's
    // position (a classifier labels objects long after they were seen).
    e_labelled = Event("labelled", kNow - 34 * kDay, i1, std::nullopt, {});
    e_no_instance = Event("added", old_event, std::nullopt, std::nullopt, {});
    e_recent = Event("removed", kNow - 1 * kDay, std::nullopt, std::nullopt, {});
    e_pinned_instance_newer = Event("moved", kNow - 2 * kDay, i2, std::nullopt, {});
    store_->Write([&](Connection& conn) {
      AppendHistory(conn, {i1, 0, old_event, false, {1, 2, 0}, e_old});
      AppendHistory(conn, {i1, 0, kNow - 35 * kDay, true, {2, 2, 0}, e_latest});
    });
  }

  std::int64_t scene_a, scene_b, scene_c, scene_d, scene_e, scene_f;
  std::int64_t ka1, ka2, kb_pinned, kb_relevant, kb_irrelevant, kb_recent, kb_segment, kb_event_segment,
      kb_event_evidence, kb_latest_segment, kd, kf;
  std::int64_t s_free, s_old_event, s_latest, i1, i2;
  std::int64_t e_old, e_latest, e_pinned_instance, e_pinned, e_labelled, e_no_instance, e_recent,
      e_pinned_instance_newer;
};

using Ids = std::vector<std::int64_t>;

INSTANTIATE_TEST_SUITE_P(Engines, forgetting, testing::BothEngines(), testing::EngineName);

TEST_P(forgetting, RemovesWhatNoReferenceNeedsAndKeepsTheRest) {
  const ForgetReport r = Run({}, false);
  EXPECT_TRUE(r.committed);
  EXPECT_EQ(r.models_state_dropped, (Ids{scene_a, scene_c}));
  EXPECT_EQ(r.models_deleted, (Ids{scene_c}));
  EXPECT_EQ(r.events_deleted, (Ids{e_old, e_no_instance}));
  Ids keyframes = {ka1, kb_irrelevant, kb_segment, kb_event_segment, kb_event_evidence, kf};
  std::sort(keyframes.begin(), keyframes.end());
  EXPECT_EQ(r.keyframes_deleted, keyframes);
  EXPECT_EQ(r.segments_deleted, (Ids{s_free, s_old_event}));
  EXPECT_EQ(r.keyframes_kept_pinned, 1);
  EXPECT_EQ(r.keyframes_kept_relevant, 1);
  EXPECT_EQ(r.keyframes_kept_referenced, 2);  // ka2 (evidence of the latest event), kb_latest_segment
  EXPECT_EQ(r.keyframes_kept_open_scene, 1);      // kd: its scene had a frame yesterday
  EXPECT_EQ(r.keyframes_of_abandoned_scenes, 1);  // kf: its scene has been open without a frame for 30 days
  EXPECT_EQ(r.events_kept_pinned, 1);
  EXPECT_EQ(r.events_kept_labelled, 1);
  EXPECT_EQ(r.events_kept_latest, 1);
  EXPECT_EQ(r.events_kept_pinned_instance, 1);
  EXPECT_GT(r.bytes_freed_estimate, 5 * 1000 + 2 * 7500);
  EXPECT_GT(r.page_count_before, 0);

  store_->Write([&](Connection& conn) {
    EXPECT_EQ(ForeignKeyCheck(conn), "");
    for (std::int64_t k : r.keyframes_deleted) EXPECT_FALSE(FindKeyframe(conn, "home", k, false)) << k;
    for (std::int64_t k : {ka2, kb_pinned, kb_relevant, kb_recent, kb_latest_segment, kd}) {
      EXPECT_TRUE(FindKeyframe(conn, "home", k, false)) << k;
    }
    const auto sa = FindScene(conn, "home", scene_a, true);
    ASSERT_TRUE(sa);
    EXPECT_TRUE(sa->background.empty() && sa->weight.empty() && sa->labels.empty());
    EXPECT_EQ(sa->state_version, 0);
    EXPECT_EQ(sa->forgotten_ns, kNow);
    EXPECT_FALSE(FindScene(conn, "home", scene_c, false));
    if (GetParam() == Engine::kSqlite) {  // SQLite's R*-tree is a table of its own; PostgreSQL's GiST index is not
      EXPECT_EQ(Count(conn, "SELECT count(*) FROM scene_models_rtree WHERE id = " + std::to_string(scene_c)), 0);
    }
    for (std::int64_t kept : {scene_b, scene_e}) {
      const auto s = FindScene(conn, "home", kept, true);
      ASSERT_TRUE(s);
      EXPECT_FALSE(s->background.empty()) << kept;
      EXPECT_FALSE(s->forgotten_ns) << kept;
    }
    for (std::int64_t ev : {e_latest, e_pinned_instance, e_pinned, e_labelled, e_recent, e_pinned_instance_newer}) {
      EXPECT_TRUE(FindEvent(conn, "home", ev)) << ev;
    }
    // The latest event of the instance still proves its position with its evidence keyframe.
    const auto latest = FindEvent(conn, "home", e_latest);
    ASSERT_EQ(latest->evidence.size(), 1u);
    EXPECT_EQ(latest->evidence[0].keyframe_id, ka2);
    EXPECT_EQ(Count(conn, "SELECT count(*) FROM event_evidence WHERE event_id = " + std::to_string(e_old)), 0);
    // The history keeps both positions; the deleted event's reference is cleared.
    const auto history = ListHistory(conn, i1);
    ASSERT_EQ(history.size(), 2u);
    EXPECT_FALSE(history[0].event_id);
    EXPECT_EQ(history[1].event_id, e_latest);
  });
  EXPECT_EQ(store_->IntegrityCheck(), "ok");

  // A second run finds nothing more to do.
  const ForgetReport again = Run({}, false);
  EXPECT_TRUE(again.models_state_dropped.empty() && again.models_deleted.empty() && again.events_deleted.empty() &&
              again.keyframes_deleted.empty() && again.segments_deleted.empty());
}

TEST_P(forgetting, DryRunReportsTheSameAndChangesNothing) {
  const std::string before = Dump();
  const ForgetReport dry = Run({}, true);
  EXPECT_EQ(Dump(), before);
  EXPECT_FALSE(dry.committed);
  EXPECT_TRUE(dry.dry_run);
  const ForgetReport real = Run({}, false);
  EXPECT_NE(Dump(), before);
  EXPECT_EQ(dry.models_state_dropped, real.models_state_dropped);
  EXPECT_EQ(dry.models_deleted, real.models_deleted);
  EXPECT_EQ(dry.events_deleted, real.events_deleted);
  EXPECT_EQ(dry.keyframes_deleted, real.keyframes_deleted);
  EXPECT_EQ(dry.segments_deleted, real.segments_deleted);
  EXPECT_EQ(dry.bytes_freed_estimate, real.bytes_freed_estimate);
}

TEST_P(forgetting, AnAbortedRunChangesNothing) {
  const std::string before = Dump();
  // Aborted in the middle of the keyframes (after models and events were already changed in the transaction).
  const auto abort_in_keyframes = [](std::string_view stage, double fraction) {
    if (stage == "keyframes" && fraction > 0.3) throw Error(ErrorCode::kInternal, "stop here");
  };
  EXPECT_THROW(Run({}, false, abort_in_keyframes), Error);
  EXPECT_EQ(Dump(), before);
  // Aborted just before the commit.
  EXPECT_THROW(Run({}, false, {}, [](Connection&, const ForgetReport&) { throw Error(ErrorCode::kInternal, "no"); }),
               Error);
  EXPECT_EQ(Dump(), before);
  // The connection is usable afterwards and a complete run works.
  EXPECT_FALSE(Run({}, false).keyframes_deleted.empty());
}

TEST_P(forgetting, PolicyFieldsSwitchRulesOff) {
  ForgetPolicy p;
  p.drop_superseded = false;
  p.keyframe_max_age_s.reset();
  p.event_max_age_s.reset();
  const std::string before = Dump();
  const ForgetReport r = Run(p, false);
  EXPECT_EQ(Dump(), before);
  EXPECT_TRUE(r.keyframes_deleted.empty() && r.events_deleted.empty() && r.models_state_dropped.empty());
  // A relevance bar of 0 keeps every keyframe (relevance >= 0); events kept, so their evidence stays too.
  ForgetPolicy keep_all;
  keep_all.keep_relevance_at_least = 0.0;
  keep_all.event_max_age_s.reset();
  const ForgetReport r2 = Run(keep_all, false);
  EXPECT_TRUE(r2.keyframes_deleted.empty());
  EXPECT_EQ(r2.keyframes_kept_relevant, 10);  // every old keyframe but the pinned one and the live open scene's
  // A longer keyframe age (15 days) leaves the 10-day-old ones.
  ForgetPolicy long_age;
  long_age.keyframe_max_age_s = 15 * 86400.0;
  EXPECT_TRUE(Run(long_age, false).keyframes_deleted.empty());
}

TEST_P(forgetting, BookkeepingMistakesFailOnTheForeignKeys) {
  // The guarantee behind "never removes what a live reference needs": deleting an evidence keyframe directly fails.
  EXPECT_THROW(store_->Write([&](Connection& conn) {
                 Statement(conn, "DELETE FROM keyframes WHERE id = ?").Bind(1, ka2).Run();
               }),
               Error);
}

TEST_P(forgetting, UnknownMapAndOpenTransactionAreRefused) {
  auto owned = OpenConnection(store_->path(), {});
  Connection& conn = *owned;
  try {
    Forget(conn, "nowhere", {}, services::ForgetKeepRules(), kNow, false);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kNotFound);
  }
  conn.Exec("BEGIN");
  EXPECT_THROW(Forget(conn, "home", {}, services::ForgetKeepRules(), kNow, false), Error);
  conn.Exec("ROLLBACK");
}

}  // namespace
}  // namespace anchordb::storage
