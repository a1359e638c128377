// The store on real databases: migrations, repositories, cascades, the spatial index, restart round trips. Tests of
// StoreEngineTest run on both engines (a SQLite file; a database on a scratch PostgreSQL 15); the PRAGMA and
// table-rebuild tests are SQLite's own.
#include "storage/sqlite.h"
#include "storage/store.h"

#include <gtest/gtest.h>

#include "schema/error.h"
#include "storage/blob_codec.h"
#include "storage/migrations.h"
#include "storage/repositories.h"
#include "tests/support/pg_scratch.h"
#include "tests/support/temp_dir.h"

namespace anchordb::storage {
namespace store_test {

StoreOptions OptionsFor(const std::string& path) {
  StoreOptions o;
  o.path = path;
  o.reader_connections = 2;
  return o;
}

LayerRecord Layer(const std::string& map, const std::string& name, std::string data) {
  LayerRecord l;
  l.map_id = map;
  l.name = name;
  l.kind = LayerKind::kProbability;
  l.meta = ProbabilityLayerMeta{{}, "occ", {}, 0};
  l.data = std::move(data);
  l.created_ns = l.updated_ns = 5;
  return l;
}

class StoreEngineTest : public ::testing::TestWithParam<Engine> {
 protected:
  testing::TestDatabase db_{GetParam()};
};
INSTANTIATE_TEST_SUITE_P(Engines, StoreEngineTest, testing::BothEngines(), testing::EngineName);

TEST_P(StoreEngineTest, MigrationsAppliedInOrderRecordedAndNotReapplied) {
  const std::string path = db_.location();
  {
    Store store(OptionsFor(path));
    const auto& r = store.migration_report();
    EXPECT_EQ(r.from_version, 0);
    EXPECT_EQ(r.to_version, EmbeddedMigrations(GetParam()).back().version);
    EXPECT_EQ(r.applied.size(), EmbeddedMigrations(GetParam()).size());
    const auto names = store.Read([](Connection& c) {
      std::vector<std::string> v;
      Statement s(c, "SELECT name FROM schema_migrations ORDER BY version");
      while (s.Step()) v.push_back(s.Text(0));
      return v;
    });
    ASSERT_EQ(names.size(), EmbeddedMigrations(GetParam()).size());
    EXPECT_EQ(names.front(), "0001_init.sql");
  }
  Store again(OptionsFor(path));
  EXPECT_TRUE(again.migration_report().applied.empty());
  EXPECT_EQ(again.migration_report().from_version, again.migration_report().to_version);
}

TEST(MigrationsTest, NewerDatabaseIsRefusedUntouched) {
  testing::TempDir dir;
  const std::string path = dir.File("future.sqlite");
  {
    SqliteConnection c(path, {});
    c.Exec("CREATE TABLE something_new (x INTEGER)");
    c.Exec("PRAGMA user_version = 999");
  }
  try {
    Store store(OptionsFor(path));
    FAIL() << "a database from a newer version was opened";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kConflict);
    EXPECT_NE(std::string(e.what()).find("999"), std::string::npos);
  }
  SqliteConnection c(path, {});
  EXPECT_EQ(UserVersion(c), 999);
  Statement s(c, "SELECT count(*) FROM sqlite_master WHERE name = 'maps'");
  s.Step();
  EXPECT_EQ(s.Int(0), 0);
}

TEST(MigrationsTest, FailingMigrationRollsBackAndKeepsVersion) {
  testing::TempDir dir;
  SqliteConnection c(dir.File("db.sqlite"), {});
  const std::vector<Migration> migrations = {{1, "0001_ok.sql", "CREATE TABLE a (x INTEGER);"},
                                             {2, "0002_bad.sql", "CREATE TABLE b (x INTEGER); THIS IS NOT SQL;"}};
  EXPECT_THROW(ApplyMigrations(c, migrations), Error);
  EXPECT_EQ(UserVersion(c), 1);
  Statement s(c, "SELECT count(*) FROM sqlite_master WHERE name = 'b'");
  s.Step();
  EXPECT_EQ(s.Int(0), 0);
}

// Migration 0016 rebuilds the events table (a new CHECK) with foreign keys off: the rows, the rows that reference
// events (instance_history.event_id; ON DELETE SET NULL would have cleared it on a cascading DROP) and the
// AUTOINCREMENT high-water mark (an id once served is never reused) all survive, and foreign keys are on after it.
TEST(MigrationsTest, TheEventsRebuildKeepsRowsReferencesAndTheIdHighWaterMark) {
  testing::TempDir dir;
  SqliteConnection c(dir.File("db.sqlite"), {});
  std::vector<Migration> before, all = EmbeddedMigrations(Engine::kSqlite);
  for (const Migration& m : all) {
    if (m.version < 16) before.push_back(m);
  }
  ApplyMigrations(c, before);
  ASSERT_EQ(UserVersion(c), 15);
  c.Exec("INSERT INTO maps (id, name, created_ns) VALUES ('m', 'm', 1)");
  c.Exec("INSERT INTO instances (map_id, kind, status, x_m, y_m, z_m, extent_x_m, extent_y_m, extent_z_m, last_seen_ns, "
         "created_ns, updated_ns) VALUES ('m', 'object', 'present', 1, 2, 0, 0.1, 0.1, 0.1, 5, 5, 5)");
  for (int i = 1; i <= 3; ++i) {
    c.Exec("INSERT INTO events (map_id, type, detection, stamp_ns, instance_id, label, created_ns) VALUES ('m', "
           "'labelled', 'dialog', " + std::to_string(i) + ", 1, 'cup', " + std::to_string(i) + ")");
  }
  c.Exec("DELETE FROM events WHERE id = 3");  // the newest id is gone; 3 must still never come back
  c.Exec("INSERT INTO instance_history (instance_id, seq, stamp_ns, present, x_m, y_m, z_m, event_id) "
         "VALUES (1, 1, 2, 1, 1, 2, 0, 2)");
  const auto count = [&](const std::string& sql) {
    Statement s(c, sql);
    s.Step();
    return s.Int(0);
  };
  EXPECT_THROW(c.Exec("INSERT INTO events (map_id, type, detection, stamp_ns, created_ns) VALUES ('m', 'labelled', "
                      "'classifier', 9, 9)"), Error);

  const MigrationReport report = ApplyMigrations(c, all);
  EXPECT_EQ(report.to_version, all.back().version);
  EXPECT_EQ(count("SELECT count(*) FROM events"), 2);
  EXPECT_EQ(count("SELECT event_id FROM instance_history WHERE instance_id = 1"), 2);
  EXPECT_EQ(count("SELECT count(*) FROM pragma_foreign_key_check"), 0);
  EXPECT_EQ(count("PRAGMA foreign_keys"), 1);
  EXPECT_EQ(count("SELECT count(*) FROM sqlite_master WHERE type = 'index' AND tbl_name = 'events'"), 2);
  c.Exec("INSERT INTO events (map_id, type, detection, stamp_ns, created_ns) VALUES ('m', 'labelled', 'classifier', 9, 9)");
  EXPECT_EQ(count("SELECT max(id) FROM events"), 4);
  // Foreign keys are enforced again: deleting the map cascades into its events.
  c.Exec("DELETE FROM maps WHERE id = 'm'");
  EXPECT_EQ(count("SELECT count(*) FROM events"), 0);
}

TEST(MigrationsTest, AMigrationWithForeignKeysOffThatBreaksAKeyChangesNothing) {
  testing::TempDir dir;
  SqliteConnection c(dir.File("db.sqlite"), {});
  const auto count = [&](const char* sql) {
    Statement s(c, sql);
    s.Step();
    return s.Int(0);
  };
  const std::string marker = kForeignKeysOffMarker;
  const std::string rebuild = marker + "\nCREATE TABLE parent_new (id INTEGER PRIMARY KEY); INSERT INTO parent_new "
                                       "SELECT id FROM parent; DROP TABLE parent; ALTER TABLE parent_new RENAME TO parent;";
  const std::string orphan = marker + "\nINSERT INTO child (parent) VALUES (7);";
  const std::vector<Migration> migrations = {
      {1, "0001_tables.sql", "CREATE TABLE parent (id INTEGER PRIMARY KEY); "
                             "CREATE TABLE child (parent INTEGER REFERENCES parent(id) ON DELETE CASCADE);"
                             "INSERT INTO parent VALUES (1); INSERT INTO child VALUES (1);"},
      {2, "0002_rebuild.sql", rebuild.c_str()},
      {3, "0003_orphan.sql", orphan.c_str()}};
  // A row orphaned before (by hand, keys off) does not block a rebuild that orphans nothing.
  ApplyMigrations(c, {migrations[0]});
  c.Exec("PRAGMA foreign_keys = OFF");
  c.Exec("INSERT INTO child (parent) VALUES (5)");
  c.Exec("PRAGMA foreign_keys = ON");
  EXPECT_THROW(ApplyMigrations(c, migrations), Error);  // 0002 applies; 0003 adds an orphan and is rolled back
  EXPECT_EQ(UserVersion(c), 2);
  EXPECT_EQ(count("SELECT count(*) FROM child"), 2);  // the rebuild's DROP did not cascade into child
  EXPECT_EQ(count("PRAGMA foreign_keys"), 1);
  // Inside an open transaction the PRAGMA would be ignored: the runner refuses instead of cascading.
  c.Exec("BEGIN");
  const std::vector<Migration> again = {migrations[0], migrations[1], {3, "0003_rebuild_again.sql", rebuild.c_str()}};
  EXPECT_THROW(ApplyMigrations(c, again), Error);
  c.Exec("ROLLBACK");
  EXPECT_EQ(UserVersion(c), 2);
}

TEST(StoreTest, PragmasAreSet) {
  testing::TempDir dir;
  Store store(OptionsFor(dir.File("db.sqlite")));
  store.Write([](Connection& c) {
    Statement j(c, "PRAGMA journal_mode");
    j.Step();
    EXPECT_EQ(j.Text(0), "wal");
    Statement f(c, "PRAGMA foreign_keys");
    f.Step();
    EXPECT_EQ(f.Int(0), 1);
    Statement s(c, "PRAGMA synchronous");
    s.Step();
    EXPECT_EQ(s.Int(0), 2);  // FULL
  });
  EXPECT_EQ(store.IntegrityCheck(), "ok");
}

TEST_P(StoreEngineTest, MapsLayersAgentsAndCascadingDelete) {
  Store store(OptionsFor(db_.location()));
  store.Write([](Connection& c) {
    InsertMap(c, {"home", "Home", 1});
    InsertMap(c, {"office", "Office", 2});
    InsertLayer(c, Layer("home", "base", "B"), {});
    InsertLayer(c, Layer("home", "surface", "S"), {"base"});
    Agent a;
    a.id = "anna";
    a.position_m = {1.0, 2.0};
    UpsertAgent(c, "home", a);
  });
  EXPECT_THROW(store.Write([](Connection& c) { InsertMap(c, {"home", "again", 3}); }), Error);
  EXPECT_THROW(store.Write([](Connection& c) { InsertLayer(c, Layer("home", "base", "X"), {}); }), Error);
  EXPECT_THROW(store.Write([](Connection& c) { InsertLayer(c, Layer("nowhere", "x", "X"), {}); }), Error);
  store.Read([](Connection& c) {
    EXPECT_EQ(ListMaps(c, "", 10).size(), 2u);
    EXPECT_EQ(ListMaps(c, "home", 10).size(), 1u);  // cursor
    EXPECT_EQ(LayerDependents(c, "home", "base"), std::vector<std::string>{"surface"});
    EXPECT_EQ(FindLayer(c, "home", "surface", true)->data, "S");
    EXPECT_TRUE(FindLayer(c, "home", "surface", false)->data.empty());
    EXPECT_EQ(FindLayer(c, "home", "surface", false)->data_bytes, 1);
    return 0;
  });
  store.Write([](Connection& c) { EXPECT_TRUE(DeleteMap(c, "home")); });
  store.Read([](Connection& c) {
    EXPECT_FALSE(FindMap(c, "home"));
    EXPECT_TRUE(ListLayers(c, "home").empty());
    EXPECT_FALSE(FindAgent(c, "home", "anna"));
    Statement s(c, GetParam() == Engine::kSqlite ? "SELECT count(*) FROM agents_rtree" : "SELECT count(*) FROM agents");
    s.Step();
    EXPECT_EQ(s.Int(0), 0);  // the spatial index follows the cascade (SQLite's R*Tree is a table of its own)
    EXPECT_TRUE(FindMap(c, "office").has_value());
    return 0;
  });
}

TEST_P(StoreEngineTest, OptimisticVersionCheckOnLayerUpdate) {
  Store store(OptionsFor(db_.location()));
  store.Write([](Connection& c) {
    InsertMap(c, {"m", "m", 1});
    InsertLayer(c, Layer("m", "l", "v1"), {});
  });
  LayerRecord next = Layer("m", "l", "v2");
  next.version = 2;
  store.Write([&](Connection& c) { UpdateLayer(c, next, 1); });
  EXPECT_THROW(store.Write([&](Connection& c) { UpdateLayer(c, next, 1); }), Error);
  EXPECT_EQ(store.Read([](Connection& c) { return FindLayer(c, "m", "l", true)->data; }), "v2");
}

TEST_P(StoreEngineTest, FailedWriteRollsBackEverything) {
  Store store(OptionsFor(db_.location()));
  EXPECT_THROW(store.Write([](Connection& c) {
                 InsertMap(c, {"m", "m", 1});
                 throw Error(ErrorCode::kUnprocessable, "changed my mind");
               }),
               Error);
  EXPECT_FALSE(store.Read([](Connection& c) { return FindMap(c, "m").has_value(); }));
}

TEST_P(StoreEngineTest, AOneStatementReadBeginsNoTransactionAndRefusesASecondStatement) {
  Store store(OptionsFor(db_.location()));
  store.Write([](Connection& c) { InsertMap(c, {"m", "m", 1}); });
  // A snapshot read is inside a transaction once its first statement ran; a one-statement read never is.
  EXPECT_TRUE(store.Read([](Connection& c) {
    FindMap(c, "m");
    return c.InTransaction();
  }));
  EXPECT_FALSE(store.ReadOneStatement([](Connection& c) {
    EXPECT_TRUE(FindMap(c, "m").has_value());
    return c.InTransaction();
  }));
  // A second statement is a programming error, refused before it runs; the connection stays usable.
  try {
    store.ReadOneStatement([](Connection& c) {
      FindMap(c, "m");
      FindMap(c, "n");
    });
    ADD_FAILURE() << "a second statement ran";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInternal);
    EXPECT_NE(std::string(e.what()).find("one-statement read"), std::string::npos) << e.what();
  }
  for (int k = 0; k < 4; ++k) {  // every reader of the pool: none kept the limit
    EXPECT_EQ(store.Read([](Connection& c) { return FindMap(c, "m").has_value() && !FindMap(c, "n").has_value(); }), true);
  }
  // It reads what was committed last.
  store.Write([](Connection& c) { InsertMap(c, {"n", "n", 2}); });
  EXPECT_TRUE(store.ReadOneStatement([](Connection& c) { return FindMap(c, "n").has_value(); }));
}

TEST_P(StoreEngineTest, ConstraintViolationsAreConflictsExceptChecksWhichAreBugs) {
  Store store(OptionsFor(db_.location()));
  const auto code_of = [&](const std::string& sql) {
    try {
      store.Write([&](Connection& c) { Statement(c, sql).Run(); });
    } catch (const Error& e) {
      return e.code();
    }
    return ErrorCode::kUnavailable;  // nothing thrown
  };
  store.Write([](Connection& c) { InsertMap(c, {"m", "m", 1}); });
  EXPECT_EQ(code_of("INSERT INTO maps (id, name, created_ns) VALUES ('m', 'again', 1)"), ErrorCode::kConflict);  // unique
  EXPECT_EQ(code_of("INSERT INTO jobs (kind, status, created_ns, updated_ns) VALUES ('x', 'odd', 1, 1)"),
            ErrorCode::kInternal);  // CHECK (status IN (...))
  EXPECT_EQ(code_of("INSERT INTO jobs (kind, status, created_ns, updated_ns) VALUES (NULL, 'queued', 1, 1)"),
            ErrorCode::kInternal);  // NOT NULL
}

TEST_P(StoreEngineTest, SpatialIndexBoundingBoxQuery) {
  Store store(OptionsFor(db_.location()));
  store.Write([](Connection& c) {
    InsertMap(c, {"m", "m", 1});
    for (int i = 0; i < 20; ++i) {
      Agent a;
      a.id = "a" + std::to_string(i);
      a.position_m = {i * 1.0, -i * 0.5};
      UpsertAgent(c, "m", a);
    }
    Agent moved;
    moved.id = "a0";
    moved.position_m = {100.0, 100.0};
    UpsertAgent(c, "m", moved);  // the update trigger moves its index entry
  });
  const auto inside = store.Read([](Connection& c) { return ListAgents(c, "m", Bbox{2.5, -4.0, 6.5, 0.0}); });
  std::vector<std::string> ids;
  for (const auto& a : inside) ids.push_back(a.id);
  EXPECT_EQ(ids, (std::vector<std::string>{"a3", "a4", "a5", "a6"}));
  const auto far = store.Read([](Connection& c) { return ListAgents(c, "m", Bbox{99, 99, 101, 101}); });
  ASSERT_EQ(far.size(), 1u);
  EXPECT_EQ(far[0].id, "a0");
}

TEST_P(StoreEngineTest, RestartRoundTripIsByteIdentical) {
  const std::string path = db_.location();
  std::vector<float> cells(400 * 400);
  for (std::size_t i = 0; i < cells.size(); ++i) cells[i] = static_cast<float>((i * 7919) % 1000) / 100.0f - 5.0f;
  const std::string blob = EncodeBlob(BlobElement::kF32, {400, 400}, AsBytes(cells), 1);
  {
    Store store(OptionsFor(path));
    store.Write([&](Connection& c) {
      InsertMap(c, {"m", "m", 1});
      InsertLayer(c, Layer("m", "l", blob), {});
    });
  }
  Store reopened(OptionsFor(path));
  const auto back = reopened.Read([](Connection& c) { return FindLayer(c, "m", "l", true); });
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->data, blob);
  EXPECT_EQ(DecodeBlob(back->data).bytes, std::string(AsBytes(cells)));
}

TEST_P(StoreEngineTest, TokensByIdAndAll) {
  Store store(OptionsFor(db_.location()));
  store.Write([](Connection& c) { InsertToken(c, {"t1", "abc", "writer", 1}); });
  EXPECT_THROW(store.Write([](Connection& c) { InsertToken(c, {"t2", "def", "root", 1}); }), Error);
  store.Read([](Connection& c) {
    EXPECT_EQ(CountTokens(c), 1);
    EXPECT_EQ(FindTokenById(c, "t1")->sha256_hex, "abc");
    EXPECT_FALSE(FindTokenById(c, "t2"));
    const auto all = ListTokens(c);
    EXPECT_EQ(all.size(), 1u);
    EXPECT_EQ(all.empty() ? "" : all[0].role, "writer");
    return 0;
  });
}

// PostgreSQL: a database of a newer schema is refused untouched; a failing file leaves nothing (transactional DDL).
TEST(PostgresMigrationsTest, NewerDatabaseIsRefusedAndAFailingFileChangesNothing) {
  testing::TestDatabase db(Engine::kPostgresql);
  {
    const auto c = OpenConnection(db.location(), {});
    c->Exec("CREATE TABLE schema_migrations (version BIGINT PRIMARY KEY, name TEXT NOT NULL, applied_ns BIGINT NOT NULL);"
            "INSERT INTO schema_migrations VALUES (999, '0999_future.sql', 1)");
  }
  try {
    Store store(OptionsFor(db.location()));
    FAIL() << "a database from a newer version was opened";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kConflict);
    EXPECT_NE(std::string(e.what()).find("999"), std::string::npos);
  }
  const auto c = OpenConnection(db.location(), {});
  EXPECT_EQ(UserVersion(*c), 999);
  c->Exec("DELETE FROM schema_migrations");
  const std::vector<Migration> migrations = {{1, "0001_ok.sql", "CREATE TABLE a (x BIGINT);"},
                                             {2, "0002_bad.sql", "CREATE TABLE b (x BIGINT); THIS IS NOT SQL;"}};
  EXPECT_THROW(ApplyMigrations(*c, migrations), Error);
  EXPECT_EQ(UserVersion(*c), 0);  // all pending files run in one transaction: the good one went with the bad one
  Statement s(*c, "SELECT count(*) FROM pg_tables WHERE tablename IN ('a', 'b')");
  s.Step();
  EXPECT_EQ(s.Int(0), 0);
}

}  // namespace
}  // namespace anchordb::storage
