// Forgetting (storage/forgetting.h) on a real SQLite file: what goes, what a live reference keeps, dry runs and
// aborted runs change nothing, no dangling reference afterwards, incremental vacuum shrinks the file; the job service
// around it (validation before queueing, results, interrupted jobs at start-up).
// Suite names are lower case so that `ctest -R forget` selects them.
#include "storage/forgetting.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <random>
#include <set>

#include "api/job_service.h"
#include "schema/error.h"
#include "storage/event_repository.h"
#include "storage/repositories.h"
#include "storage/scene_repository.h"
#include "storage/store.h"
#include "tests/support/temp_dir.h"

namespace anchordb::storage {
namespace {

constexpr std::int64_t kSecond = 1000000000LL;
constexpr std::int64_t kDay = 86400 * kSecond;
constexpr std::int64_t kNow = 20000 * kDay;

// Every row of every table (rtree shadow tables included), sorted: equal dumps mean nothing changed.
std::string DumpAll(Connection& c) {
  std::vector<std::string> tables;
  {
    Statement s(c, "SELECT name FROM sqlite_master WHERE type = 'table' AND sql NOT LIKE 'CREATE VIRTUAL%' ORDER BY name");
    while (s.Step()) tables.push_back(s.Text(0));
  }
  std::string out;
  for (const std::string& t : tables) {
    std::string columns;
    Statement info(c, "SELECT name FROM pragma_table_info(?)");
    info.Bind(1, t);
    while (info.Step()) columns += (columns.empty() ? "quote(\"" : " || ',' || quote(\"") + info.Text(0) + "\")";
    std::vector<std::string> rows;
    Statement s(c, "SELECT " + columns + " FROM \"" + t + "\"");
    while (s.Step()) rows.push_back(s.Text(0));
    std::sort(rows.begin(), rows.end());
    out += "[" + t + "]\n";
    for (const auto& r : rows) out += r + "\n";
  }
  return out;
}

std::string ForeignKeyCheck(Connection& c) {
  Statement s(c, "PRAGMA foreign_key_check");
  std::string out;
  while (s.Step()) out += s.Text(0) + " rowid " + std::to_string(s.Int(1)) + " -> " + s.Text(2) + "; ";
  return out;
}

std::int64_t Count(Connection& c, const std::string& sql) {
  Statement s(c, sql);
  return s.Step() ? s.Int(0) : -1;
}

class ForgetFixture : public ::testing::Test {
 protected:
  void SetUp() override {
    StoreOptions o;
    o.path = dir_.File("db.sqlite");
    o.reader_connections = 1;
    store_ = std::make_unique<Store>(o);
    store_->Write([](Connection& c) { InsertMap(c, {"home", "test", 1}); });
  }

  std::int64_t Scene(const std::string& status, std::optional<std::int64_t> ended_ns,
                     std::optional<std::int64_t> superseded_by, std::size_t state_bytes = 3000) {
    return store_->Write([&](Connection& c) {
      SceneRecord r;
      r.map_id = "home";
      r.status = "observing";
      r.intrinsics_json = R"({"width":8,"height":6,"fx":5,"fy":5,"cx":4,"cy":3})";
      r.pose_json = R"({"position":[0,0,0],"orientation":[0,0,0,1]})";
      r.params_json = "{}";
      r.started_ns = kNow - 60 * kDay;
      r.id = InsertScene(c, r);
      r.background = std::string(state_bytes, 'b');
      r.weight = std::string(state_bytes, 'w');
      r.labels = std::string(state_bytes / 2, 'l');
      r.frames = 10;
      r.state_version = 1;
      UpdateSceneState(c, r, 0);
      UpdateSceneStatus(c, r.id, status, ended_ns, superseded_by);
      return r.id;
    });
  }

  std::int64_t Keyframe(std::int64_t scene, std::int64_t stamp_ns, bool pinned = false, double relevance = 0.0,
                        std::size_t bytes = 500) {
    return store_->Write([&](Connection& c) {
      KeyframeRecord k;
      k.map_id = "home";
      k.scene_id = scene;
      k.kind = "manual";
      k.stamp_ns = stamp_ns;
      k.width = 8;
      k.height = 6;
      k.depth = RandomBytes(bytes);
      k.background = RandomBytes(bytes);
      k.raw_bytes = 2 * 2 * 48;
      k.stored_bytes = static_cast<std::int64_t>(2 * bytes);
      k.pinned = pinned;
      const std::int64_t id = InsertKeyframe(c, k);
      SetKeyframeRelevance(c, "home", id, relevance);  // InsertKeyframe leaves relevance at its default 0
      return id;
    });
  }

  std::int64_t Segment(std::int64_t keyframe) {
    return store_->Write([&](Connection& c) {
      SegmentRecord s;
      s.map_id = "home";
      s.keyframe_id = keyframe;
      s.points = 40;
      s.sample = std::string(48, 's');
      return InsertSegment(c, s);
    });
  }

  std::int64_t Instance(bool pinned) {
    return store_->Write([&](Connection& c) {
      InstanceRecord r;
      r.map_id = "home";
      r.pinned = pinned;
      r.last_seen_ns = r.created_ns = r.updated_ns = kNow - 30 * kDay;
      return InsertInstance(c, r);
    });
  }

  std::int64_t Event(const std::string& type, std::int64_t stamp_ns, std::optional<std::int64_t> instance,
                     std::optional<std::int64_t> segment, std::vector<EvidenceRecord> evidence, bool pinned = false) {
    return store_->Write([&](Connection& c) {
      EventRecord e;
      e.map_id = "home";
      e.type = type;
      e.detection = type == "labelled" ? "dialog" : "observed";
      e.stamp_ns = stamp_ns;
      e.instance_id = instance;
      e.segment_id = segment;
      e.pinned = pinned;
      e.created_ns = stamp_ns;
      e.evidence = std::move(evidence);
      return InsertEvent(c, e);
    });
  }

  std::string RandomBytes(std::size_t n) {
    std::string s(n, '\0');
    for (char& ch : s) ch = static_cast<char>(rng_() & 0xff);
    return s;
  }

  std::string Dump() { return store_->Write([](Connection& c) { return DumpAll(c); }); }

  ForgetReport Run(const ForgetPolicy& policy, bool dry_run, const ForgetProgress& progress = {},
                   const ForgetBeforeCommit& before_commit = {}) {
    Connection c(store_->path(), {});
    return Forget(c, "home", policy, kNow, dry_run, progress, before_commit);
  }

  testing::TempDir dir_;
  std::unique_ptr<Store> store_;
  std::mt19937 rng_{7};
};

// The scenario of most tests: every rule of forgetting, each with a row it removes and a row it must keep.
class forgetting : public ForgetFixture {
 protected:
  void SetUp() override {
    ForgetFixture::SetUp();
    const std::int64_t old_kf = kNow - 10 * kDay, old_event = kNow - 40 * kDay;
    scene_b = Scene("closed", kNow - 20 * kDay, std::nullopt);
    scene_a = Scene("superseded", kNow - 50 * kDay, scene_b);   // state dropped; row kept (its keyframe ka2 is evidence)
    scene_c = Scene("superseded", kNow - 50 * kDay, scene_b);   // no keyframes: state dropped and row deleted
    scene_d = Scene("observing", std::nullopt, std::nullopt);  // never closed: keyframes stay
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
    s_free = Segment(kb_segment);
    s_old_event = Segment(kb_event_segment);
    s_latest = Segment(kb_latest_segment);
    i1 = Instance(false);
    i2 = Instance(true);
    e_old = Event("removed", old_event, i1, s_old_event, {{kb_event_evidence, "before"}});
    e_latest = Event("added", kNow - 35 * kDay, i1, s_latest, {{ka2, "after"}});
    e_pinned_instance = Event("added", old_event, i2, std::nullopt, {});
    e_pinned = Event("added", old_event, std::nullopt, std::nullopt, {}, true);
    e_labelled = Event("labelled", old_event, std::nullopt, std::nullopt, {});
    e_no_instance = Event("added", old_event, std::nullopt, std::nullopt, {});
    e_recent = Event("removed", kNow - 1 * kDay, std::nullopt, std::nullopt, {});
    e_pinned_instance_newer = Event("moved", kNow - 2 * kDay, i2, std::nullopt, {});
    store_->Write([&](Connection& conn) {
      AppendHistory(conn, {i1, 0, old_event, false, {1, 2, 0}, e_old});
      AppendHistory(conn, {i1, 0, kNow - 35 * kDay, true, {2, 2, 0}, e_latest});
    });
  }

  std::int64_t scene_a, scene_b, scene_c, scene_d, scene_e;
  std::int64_t ka1, ka2, kb_pinned, kb_relevant, kb_irrelevant, kb_recent, kb_segment, kb_event_segment,
      kb_event_evidence, kb_latest_segment, kd;
  std::int64_t s_free, s_old_event, s_latest, i1, i2;
  std::int64_t e_old, e_latest, e_pinned_instance, e_pinned, e_labelled, e_no_instance, e_recent,
      e_pinned_instance_newer;
};

using Ids = std::vector<std::int64_t>;

TEST_F(forgetting, RemovesWhatNoReferenceNeedsAndKeepsTheRest) {
  const ForgetReport r = Run({}, false);
  EXPECT_TRUE(r.committed);
  EXPECT_EQ(r.models_state_dropped, (Ids{scene_a, scene_c}));
  EXPECT_EQ(r.models_deleted, (Ids{scene_c}));
  EXPECT_EQ(r.events_deleted, (Ids{e_old, e_no_instance}));
  Ids keyframes = {ka1, kb_irrelevant, kb_segment, kb_event_segment, kb_event_evidence};
  std::sort(keyframes.begin(), keyframes.end());
  EXPECT_EQ(r.keyframes_deleted, keyframes);
  EXPECT_EQ(r.segments_deleted, (Ids{s_free, s_old_event}));
  EXPECT_EQ(r.keyframes_kept_pinned, 1);
  EXPECT_EQ(r.keyframes_kept_relevant, 1);
  EXPECT_EQ(r.keyframes_kept_referenced, 2);  // ka2 (evidence of the latest event), kb_latest_segment
  EXPECT_EQ(r.keyframes_kept_open_scene, 1);
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
    EXPECT_EQ(Count(conn, "SELECT count(*) FROM scene_models_rtree WHERE id = " + std::to_string(scene_c)), 0);
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

TEST_F(forgetting, DryRunReportsTheSameAndChangesNothing) {
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
  EXPECT_EQ(dry.ToJson()["keyframes_deleted"], real.ToJson()["keyframes_deleted"]);
}

TEST_F(forgetting, AnAbortedRunChangesNothing) {
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

TEST_F(forgetting, PolicyFieldsSwitchRulesOff) {
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
  EXPECT_EQ(r2.keyframes_kept_relevant, 9);  // every old keyframe of a closed scene but the pinned one
  // A longer keyframe age (15 days) leaves the 10-day-old ones.
  ForgetPolicy long_age;
  long_age.keyframe_max_age_s = 15 * 86400.0;
  EXPECT_TRUE(Run(long_age, false).keyframes_deleted.empty());
}

TEST_F(forgetting, BookkeepingMistakesFailOnTheForeignKeys) {
  // The guarantee behind "never removes what a live reference needs": deleting an evidence keyframe directly fails.
  EXPECT_THROW(store_->Write([&](Connection& conn) {
                 Statement(conn, "DELETE FROM keyframes WHERE id = ?").Bind(1, ka2).Run();
               }),
               Error);
}

TEST_F(forgetting, UnknownMapAndOpenTransactionAreRefused) {
  Connection conn(store_->path(), {});
  try {
    Forget(conn, "nowhere", {}, kNow, false);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kNotFound);
  }
  conn.Exec("BEGIN");
  EXPECT_THROW(Forget(conn, "home", {}, kNow, false), Error);
  conn.Exec("ROLLBACK");
}

Error ParseError(const std::string& text) {
  try {
    ParseForgetRequest(nlohmann::json::parse(text));
  } catch (const Error& e) {
    return e;
  }
  return Error(ErrorCode::kInternal, "no error for " + text);
}

TEST(forgetting_policy, ParsesDefaultsAndValidatesStrictly) {
  const ForgetRequest defaults = ParseForgetRequest(nlohmann::json::object());
  EXPECT_FALSE(defaults.dry_run);
  EXPECT_TRUE(defaults.policy.drop_superseded);
  EXPECT_EQ(defaults.policy.keyframe_max_age_s, 7 * 86400.0);
  EXPECT_EQ(defaults.policy.event_max_age_s, 30 * 86400.0);
  EXPECT_EQ(defaults.policy.keep_relevance_at_least, 0.5);
  EXPECT_FALSE(defaults.policy.vacuum);
  const ForgetRequest r = ParseForgetRequest(nlohmann::json::parse(
      R"({"policy": {"superseded_models": false, "keyframe_max_age_s": 60, "keep_relevance_at_least": 1,
          "event_max_age_s": null, "vacuum": true}, "dry_run": true})"));
  EXPECT_TRUE(r.dry_run);
  EXPECT_FALSE(r.policy.drop_superseded);
  EXPECT_EQ(r.policy.keyframe_max_age_s, 60.0);
  EXPECT_FALSE(r.policy.event_max_age_s);
  EXPECT_EQ(r.policy.keep_relevance_at_least, 1.0);
  EXPECT_TRUE(r.policy.vacuum);
  // Round trip of the stored form.
  EXPECT_EQ(ParseForgetRequest({{"policy", ToJson(r.policy)}, {"dry_run", true}}).policy.keyframe_max_age_s, 60.0);

  struct Case {
    const char* body;
    ErrorCode code;
    const char* field;
  };
  const Case cases[] = {
      {R"({"policy": {"keyframe_max_age_s": -1}})", ErrorCode::kUnprocessable, "policy.keyframe_max_age_s"},
      {R"({"policy": {"event_max_age_s": -0.5}})", ErrorCode::kUnprocessable, "policy.event_max_age_s"},
      {R"({"policy": {"event_max_age_s": 1e12}})", ErrorCode::kUnprocessable, "policy.event_max_age_s"},
      {R"({"policy": {"keep_relevance_at_least": 1.5}})", ErrorCode::kUnprocessable, "policy.keep_relevance_at_least"},
      {R"({"policy": {"keep_relevance_at_least": -0.1}})", ErrorCode::kUnprocessable, "policy.keep_relevance_at_least"},
      {R"({"policy": {"keyframes": 1}})", ErrorCode::kInvalidArgument, "policy.keyframes"},
      {R"({"polcy": {}})", ErrorCode::kInvalidArgument, "polcy"},
      {R"({"policy": {"keyframe_max_age_s": "7d"}})", ErrorCode::kInvalidArgument, "policy.keyframe_max_age_s"},
      {R"({"policy": {"vacuum": 1}})", ErrorCode::kInvalidArgument, "policy.vacuum"},
      {R"({"policy": {"superseded_models": "yes"}})", ErrorCode::kInvalidArgument, "policy.superseded_models"},
      {R"({"policy": [1]})", ErrorCode::kInvalidArgument, "policy"},
      {R"({"dry_run": "true"})", ErrorCode::kInvalidArgument, "dry_run"},
  };
  for (const Case& c : cases) {
    const Error e = ParseError(c.body);
    EXPECT_EQ(e.code(), c.code) << c.body << ": " << e.what();
    EXPECT_EQ(e.field(), c.field) << c.body;
  }
}

// Incremental vacuum: the first vacuum switches a file in auto_vacuum=NONE mode to INCREMENTAL (VACUUM), later ones
// run PRAGMA incremental_vacuum; both shrink the file on disk.
class forgetting_vacuum : public ForgetFixture {};

TEST_F(forgetting_vacuum, ShrinksTheFile) {
  const std::int64_t closed = Scene("closed", kNow - 20 * kDay, std::nullopt);
  const auto fill = [&](int n) {
    for (int i = 0; i < n; ++i) Keyframe(closed, kNow - 10 * kDay, false, 0.0, 20000);
    Keyframe(closed, kNow - 1 * kDay, false, 0.0, 20000);  // a recent one stays
  };
  fill(150);
  ForgetPolicy p;
  p.vacuum = true;
  const ForgetReport first = Run(p, false);
  EXPECT_EQ(first.keyframes_deleted.size(), 150u);
  EXPECT_EQ(first.vacuum_mode, "switched_to_incremental");
  EXPECT_GT(first.file_bytes_before, 150 * 40000);
  EXPECT_LT(first.file_bytes_after, first.file_bytes_before / 10);
  EXPECT_EQ(first.freelist_after_vacuum, 0);
  const std::int64_t size_first = DatabaseFileBytes(store_->path());
  EXPECT_EQ(size_first, first.file_bytes_after);
  store_->Write([](Connection& c) { EXPECT_EQ(Count(c, "PRAGMA auto_vacuum"), 2); });

  fill(100);
  const std::int64_t grown = DatabaseFileBytes(store_->path());
  const ForgetReport second = Run(p, false);
  EXPECT_EQ(second.keyframes_deleted.size(), 100u);
  EXPECT_EQ(second.vacuum_mode, "incremental");
  EXPECT_GT(grown, 100 * 40000);
  EXPECT_LT(second.file_bytes_after, grown / 5);
  EXPECT_EQ(second.freelist_after_vacuum, 0);
  std::printf("[ figures ] vacuum (switch): %lld -> %lld bytes; incremental: %lld -> %lld bytes\n",
              static_cast<long long>(first.file_bytes_before), static_cast<long long>(first.file_bytes_after),
              static_cast<long long>(second.file_bytes_before), static_cast<long long>(second.file_bytes_after));
  EXPECT_EQ(store_->IntegrityCheck(), "ok");
  store_->Write([](Connection& c) { EXPECT_EQ(ForeignKeyCheck(c), ""); });
  // A dry run with vacuum does not vacuum.
  EXPECT_EQ(Run(p, true).vacuum_mode, "skipped (dry run)");
}

}  // namespace
}  // namespace anchordb::storage

namespace anchordb::api {
namespace {

using storage::Connection;
using storage::Statement;

class forgetting_job : public ::testing::Test {
 protected:
  void SetUp() override {
    storage::StoreOptions o;
    o.path = dir_.File("db.sqlite");
    o.reader_connections = 1;
    store_ = std::make_unique<storage::Store>(o);
    store_->Write([](Connection& c) { storage::InsertMap(c, {"home", "test", 1}); });
  }
  std::int64_t Jobs() {
    return store_->Read([](Connection& c) {
      Statement s(c, "SELECT count(*) FROM jobs");
      s.Step();
      return s.Int(0);
    });
  }
  testing::TempDir dir_;
  std::unique_ptr<storage::Store> store_;
};

TEST_F(forgetting_job, BadInputQueuesNothingAndAGoodJobSucceeds) {
  JobService jobs(*store_);
  EXPECT_THROW(jobs.SubmitForget("home", Json::parse(R"({"policy": {"keyframe_max_age_s": -1}})")), Error);
  EXPECT_THROW(jobs.SubmitForget("home", Json::parse(R"({"policy": {"nonsense": 1}})")), Error);
  try {
    jobs.SubmitForget("nowhere", Json::object());
    FAIL() << "no error for an unknown map";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kNotFound);
  }
  EXPECT_EQ(Jobs(), 0);
  const Json submitted = jobs.SubmitForget("home", Json::parse(R"({"dry_run": true})"));
  EXPECT_EQ(submitted["status"], "queued");
  ASSERT_TRUE(jobs.WaitIdle(30));
  const Json job = jobs.Get(submitted["job"].get<std::int64_t>());
  EXPECT_EQ(job["status"], "succeeded") << job.dump();
  EXPECT_EQ(job["kind"], "forget");
  EXPECT_EQ(job["map"], "home");
  EXPECT_EQ(job["progress"], 1.0);
  EXPECT_EQ(job["request"]["dry_run"], true);
  EXPECT_EQ(job["result"]["dry_run"], true);
  EXPECT_EQ(job["result"]["features_deduplicated"], 0);
  EXPECT_TRUE(job["error"].is_null());
  const Json real = jobs.SubmitForget("home", Json::parse(R"({"policy": {"vacuum": true}})"));
  ASSERT_TRUE(jobs.WaitIdle(30));
  const Json done = jobs.Get(real["job"].get<std::int64_t>());
  EXPECT_EQ(done["status"], "succeeded") << done.dump();
  EXPECT_EQ(done["result"]["committed"], true);
  EXPECT_EQ(done["result"]["vacuum"]["mode"], "switched_to_incremental");
  try {
    jobs.Get(999);
    FAIL() << "no error for an unknown job";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kNotFound);
  }
}

TEST_F(forgetting_job, JobsFoundRunningOrQueuedAtStartAreMarkedInterrupted) {
  store_->Write([](Connection& c) {
    c.Exec("INSERT INTO jobs (kind, map_id, status, stage, progress, created_ns, updated_ns) VALUES "
           "('forget', 'home', 'running', 'keyframes', 0.5, 1, 1), ('forget', 'home', 'queued', '', 0, 2, 2), "
           "('forget', 'home', 'succeeded', 'done', 1, 3, 3)");
  });
  JobService jobs(*store_);
  EXPECT_EQ(jobs.interrupted_at_start(), 2);
  const Json running = jobs.Get(1), queued = jobs.Get(2), done = jobs.Get(3);
  EXPECT_EQ(running["status"], "failed");
  EXPECT_EQ(running["error"], "interrupted by a server stop (stage keyframes)");
  EXPECT_EQ(queued["status"], "failed");
  EXPECT_EQ(queued["error"], "interrupted by a server stop");
  EXPECT_EQ(done["status"], "succeeded");
}

}  // namespace
}  // namespace anchordb::api
