// Online backup (storage/backup.h) on real SQLite files, with another connection writing during the copy.
#include "storage/backup.h"

#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <thread>

#include "schema/error.h"
#include "storage/sqlite.h"
#include "tests/support/temp_dir.h"

namespace anchordb::storage {
namespace backup_test {

ConnectionOptions Writable() {
  ConnectionOptions o;
  o.busy_timeout_ms = 10000;
  return o;
}

std::int64_t Scalar(Connection& c, const char* sql) {
  Statement s(c, sql);
  EXPECT_TRUE(s.Step());
  return s.Int(0);
}

// A table whose rows come in committed pairs (+v, -v): every consistent snapshot has an even count and sum 0.
void Fill(Connection& c, int first, int pairs) {
  c.Exec("BEGIN IMMEDIATE");
  for (int i = first; i < first + pairs; ++i) {
    Statement(c, "INSERT INTO ledger (v, pad) VALUES (?, randomblob(3000))").Bind(1, std::int64_t{i}).Run();
    Statement(c, "INSERT INTO ledger (v, pad) VALUES (?, randomblob(3000))").Bind(1, -std::int64_t{i}).Run();
  }
  c.Exec("COMMIT");
}

TEST(BackupTest, CopyTakenWhileAnotherConnectionWritesIsConsistentAndComplete) {
  testing::TempDir dir;
  const std::string db = dir.File("live.sqlite");
  SqliteConnection writer(db, Writable());
  writer.Exec("CREATE TABLE ledger (id INTEGER PRIMARY KEY, v INTEGER NOT NULL, pad BLOB)");
  Fill(writer, 1, 2000);  // ~12 MB: many steps of 256 pages
  const std::int64_t rows_before = Scalar(writer, "SELECT COUNT(*) FROM ledger");

  std::atomic<bool> stop{false};
  std::atomic<int> commits{0};
  std::thread load([&] {
    SqliteConnection c(db, Writable());
    for (int k = 0; !stop; ++k) {
      Fill(c, 100000 + 10 * k, 5);
      ++commits;
    }
  });
  std::vector<double> fractions;
  const std::string copy = dir.File("backups/copy.sqlite");
  const BackupReport r = Backup(db, copy, 10000, [&](double f) {
    fractions.push_back(f);
    // Let the writer commit between steps, so that the copy has to cope with a changing source.
    if (fractions.size() % 8 == 0) {
      const int seen = commits;
      while (commits == seen && !stop) std::this_thread::yield();
    }
  });
  stop = true;
  load.join();

  EXPECT_EQ(r.integrity, "ok");
  EXPECT_EQ(r.file, std::filesystem::absolute(copy).lexically_normal().string());
  EXPECT_EQ(r.bytes, static_cast<std::int64_t>(std::filesystem::file_size(copy)));
  EXPECT_GT(r.pages, 2000);
  EXPECT_FALSE(std::filesystem::exists(copy + ".partial"));
  ASSERT_FALSE(fractions.empty());
  EXPECT_GT(commits.load(), 0);
  std::printf("backup: %lld pages, %d restarts, %zu progress calls, %d concurrent commits, %.3f s\n",
              static_cast<long long>(r.pages), r.restarts, fractions.size(), commits.load(), r.duration_s);

  ConnectionOptions ro;
  ro.read_only = true;
  SqliteConnection c(copy, ro);
  const std::int64_t rows = Scalar(c, "SELECT COUNT(*) FROM ledger");
  EXPECT_GE(rows, rows_before);                                   // nothing committed before the backup is missing
  EXPECT_EQ(rows % 2, 0);                                         // no half transaction
  EXPECT_EQ(Scalar(c, "SELECT COALESCE(SUM(v), 0) FROM ledger"), 0);
  Statement check(c, "PRAGMA integrity_check");
  ASSERT_TRUE(check.Step());
  EXPECT_EQ(check.Text(0), "ok");
}

TEST(BackupTest, ExistingTargetIsRefusedAndAnAbortedCopyLeavesNoFile) {
  testing::TempDir dir;
  const std::string db = dir.File("live.sqlite");
  {
    SqliteConnection writer(db, Writable());
    writer.Exec("CREATE TABLE ledger (id INTEGER PRIMARY KEY, v INTEGER NOT NULL, pad BLOB)");
    Fill(writer, 1, 500);
  }
  const std::string taken = dir.File("taken.sqlite");
  { std::FILE* f = std::fopen(taken.c_str(), "w"); std::fputs("mine", f); std::fclose(f); }
  try {
    Backup(db, taken, 1000);
    ADD_FAILURE() << "an existing file was overwritten";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kConflict);
  }
  EXPECT_EQ(std::filesystem::file_size(taken), 4u);  // untouched

  const std::string aborted = dir.File("aborted.sqlite");
  int calls = 0;
  EXPECT_THROW(Backup(db, aborted, 1000, [&](double) {
                 if (++calls == 2) throw Error(ErrorCode::kOverloaded, "stop");
               }, 16),
               Error);
  EXPECT_EQ(calls, 2);
  EXPECT_FALSE(std::filesystem::exists(aborted));
  EXPECT_FALSE(std::filesystem::exists(aborted + ".partial"));
}

TEST(BackupTest, FileNamesCarryTheDatabaseStemTheUtcTimeAndTheLabel) {
  // 2026-11-23T05:30:07Z
  const std::int64_t t = 1795411807LL * 1'000'000'000LL;
  EXPECT_EQ(BackupFileName("/b", "/var/home.sqlite", t, ""), "/b/home-20261123T053007Z.sqlite");
  EXPECT_EQ(BackupFileName("/b", "home.sqlite", t, "nightly"), "/b/home-20261123T053007Z-nightly.sqlite");
}

}  // namespace
}  // namespace anchordb::storage
