#pragma once
// Internal to tests/storage/forgetting*_test.cc: a store on either engine (a SQLite file or a scratch PostgreSQL
// database) with one map ("home"), builders for
// scene models, keyframes, segments, instances and events at chosen ages, dumps of every row, and Forget run at kNow.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "services/jobs/forget_job.h"
#include "storage/event_repository.h"
#include "storage/forgetting.h"
#include "storage/repositories.h"
#include "storage/scene_repository.h"
#include "storage/store.h"
#include "tests/support/pg_scratch.h"
#include "tests/support/test_store.h"

namespace anchordb::storage::forget_test {

constexpr std::int64_t kSecond = 1000000000LL;
constexpr std::int64_t kDay = 86400 * kSecond;
constexpr std::int64_t kNow = 20000 * kDay;

// Every row of every table (SQLite's rtree shadow tables included), sorted: equal dumps mean nothing changed.
inline std::string DumpAll(Connection& c) {
  const bool sqlite = c.engine() == Engine::kSqlite;
  std::vector<std::string> tables;
  {
    Statement s(c, sqlite ? "SELECT name FROM sqlite_master WHERE type = 'table' AND sql NOT LIKE 'CREATE VIRTUAL%' "
                            "ORDER BY name"
                          : "SELECT tablename FROM pg_tables WHERE schemaname = current_schema() ORDER BY tablename");
    while (s.Step()) tables.push_back(s.Text(0));
  }
  std::string out;
  for (const std::string& t : tables) {
    std::string row = "row_to_json(t)::text";
    if (sqlite) {
      row.clear();
      Statement info(c, "SELECT name FROM pragma_table_info(?)");
      info.Bind(1, t);
      while (info.Step()) row += (row.empty() ? "quote(\"" : " || ',' || quote(\"") + info.Text(0) + "\")";
    }
    std::vector<std::string> rows;
    Statement s(c, "SELECT " + row + " FROM \"" + t + "\" AS t");
    while (s.Step()) rows.push_back(s.Text(0));
    std::sort(rows.begin(), rows.end());
    out += "[" + t + "]\n";
    for (const auto& r : rows) out += r + "\n";
  }
  return out;
}

// Rows whose foreign key points nowhere. PostgreSQL checks every foreign key at the statement (none is deferred), so
// a dangling row cannot exist there and the check is SQLite's alone.
inline std::string ForeignKeyCheck(Connection& c) {
  if (c.engine() != Engine::kSqlite) return "";
  Statement s(c, "PRAGMA foreign_key_check");
  std::string out;
  while (s.Step()) out += s.Text(0) + " rowid " + std::to_string(s.Int(1)) + " -> " + s.Text(2) + "; ";
  return out;
}

inline std::int64_t Count(Connection& c, const std::string& sql) {
  Statement s(c, sql);
  return s.Step() ? s.Int(0) : -1;
}

class ForgetFixture : public ::testing::TestWithParam<Engine> {
 protected:
  void SetUp() override { store_ = testing::OpenStoreWithMaps(db_.location(), {"home"}); }

  std::int64_t Scene(const std::string& status, std::optional<std::int64_t> ended_ns,
                     std::optional<std::int64_t> superseded_by, std::size_t state_bytes = 3000,
                     std::optional<std::int64_t> last_frame_ns = std::nullopt) {
    return store_->Write([&](Connection& c) {
      SceneRecord r;
      r.map_id = "home";
      r.status = "observing";
      r.camera = {8, 6, 5, 5, 4, 3};
      r.started_ns = kNow - 60 * kDay;
      r.id = InsertScene(c, r);
      r.background = std::string(state_bytes, 'b');
      r.weight = std::string(state_bytes, 'w');
      r.labels = std::string(state_bytes / 2, 'l');
      r.frames = 10;
      r.state_version = 1;
      r.last_frame_ns = last_frame_ns;
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
    auto c = OpenConnection(store_->path(), {});
    return Forget(*c, "home", policy, services::ForgetKeepRules(), kNow, dry_run, progress, before_commit);
  }

  testing::TestDatabase db_{GetParam()};
  std::unique_ptr<Store> store_;
  std::mt19937 rng_{7};
};

}  // namespace anchordb::storage::forget_test
