#include "storage/backup.h"

#include <fcntl.h>
#include <sqlite3.h>
#include <unistd.h>

#include <chrono>
#include <ctime>
#include <filesystem>
#include <thread>

#include "schema/error.h"
#include "storage/sqlite.h"

namespace anchordb::storage {
namespace {

namespace fs = std::filesystem;

// A database handle for the destination, closed on every path.
struct Handle {
  sqlite3* db = nullptr;
  ~Handle() { sqlite3_close_v2(db); }
};

void SyncPath(const std::string& path, bool directory) {
  const int fd = ::open(path.c_str(), directory ? (O_RDONLY | O_DIRECTORY) : O_RDONLY);
  if (fd < 0) throw Error(ErrorCode::kInternal, "backup: cannot open " + path + " to sync it");
  const int rc = ::fsync(fd);
  ::close(fd);
  if (rc != 0) throw Error(ErrorCode::kInternal, "backup: fsync of " + path + " failed");
}

// Removes the partial copy unless the backup got to its rename.
struct PartialFile {
  std::string path;
  bool keep = false;
  ~PartialFile() {
    if (keep) return;
    std::error_code ignored;
    fs::remove(path, ignored);
    fs::remove(path + "-journal", ignored);
  }
};

}  // namespace

std::string BackupFileName(const std::string& directory, const std::string& db_path, std::int64_t now_ns,
                           const std::string& label) {
  const std::time_t seconds = static_cast<std::time_t>(now_ns / 1'000'000'000);
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y%m%dT%H%M%SZ", &utc);
  std::string name = fs::path(db_path).stem().string() + "-" + stamp;
  if (!label.empty()) name += "-" + label;
  return (fs::path(directory) / (name + ".sqlite")).string();
}

BackupReport Backup(const std::string& source_path, const std::string& dest_path, int busy_timeout_ms,
                    const BackupProgress& progress, int pages_per_step) {
  const auto start = std::chrono::steady_clock::now();
  if (IsPostgresUri(source_path)) {
    throw Error(ErrorCode::kInvalidArgument,
                "anchordb backs up a SQLite file only; a PostgreSQL database is backed up with PostgreSQL's own tools "
                "(pg_basebackup for the cluster with point-in-time recovery, or pg_dump -Fc for this database)");
  }
  std::error_code ec;
  if (fs::exists(dest_path, ec)) throw Error(ErrorCode::kConflict, "backup file " + dest_path + " exists already", "file");
  const fs::path parent = fs::path(dest_path).parent_path();
  if (!parent.empty()) {
    fs::create_directories(parent, ec);
    if (ec) throw Error(ErrorCode::kInternal, "backup: cannot create " + parent.string() + ": " + ec.message());
  }
  ConnectionOptions source_options;
  source_options.read_only = true;
  source_options.busy_timeout_ms = busy_timeout_ms;
  SqliteConnection source(source_path, source_options);

  PartialFile partial{dest_path + ".partial"};
  fs::remove(partial.path, ec);  // left by an earlier crash
  Handle dest;
  if (sqlite3_open_v2(partial.path.c_str(), &dest.db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) != SQLITE_OK) {
    throw Error(ErrorCode::kInternal, "backup: cannot create " + partial.path + ": " + sqlite3_errmsg(dest.db));
  }
  sqlite3_backup* b = sqlite3_backup_init(dest.db, "main", source.handle(), "main");
  if (!b) throw Error(ErrorCode::kInternal, std::string("backup: ") + sqlite3_errmsg(dest.db));
  BackupReport report;
  int rc = SQLITE_OK;
  int last_remaining = -1;
  try {
    for (;;) {
      // After a few restarts (writers changed the source between steps) the rest goes in one step: one read
      // transaction, so it finishes whatever the write load.
      const int step = report.restarts >= 3 ? -1 : pages_per_step;
      rc = sqlite3_backup_step(b, step);
      const int remaining = sqlite3_backup_remaining(b), total = sqlite3_backup_pagecount(b);
      if (last_remaining >= 0 && remaining > last_remaining) ++report.restarts;
      last_remaining = remaining;
      if (rc == SQLITE_DONE) break;
      if (rc == SQLITE_BUSY || rc == SQLITE_LOCKED) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
      } else if (rc != SQLITE_OK) {
        break;
      }
      if (progress && total > 0) progress(static_cast<double>(total - remaining) / total);
    }
  } catch (...) {
    sqlite3_backup_finish(b);
    throw;
  }
  report.pages = sqlite3_backup_pagecount(b);
  const int finish = sqlite3_backup_finish(b);
  if (rc != SQLITE_DONE || finish != SQLITE_OK) {
    throw Error(ErrorCode::kInternal, std::string("backup failed: ") + sqlite3_errstr(rc != SQLITE_DONE ? rc : finish) +
                                          " (SQLite result code " + std::to_string(rc) + ")");
  }
  sqlite3_stmt* check = nullptr;
  sqlite3_prepare_v2(dest.db, "PRAGMA integrity_check", -1, &check, nullptr);
  report.integrity = check && sqlite3_step(check) == SQLITE_ROW
                         ? reinterpret_cast<const char*>(sqlite3_column_text(check, 0))
                         : std::string("integrity_check did not run: ") + sqlite3_errmsg(dest.db);
  sqlite3_finalize(check);
  sqlite3_close_v2(dest.db);
  dest.db = nullptr;
  if (report.integrity != "ok") throw Error(ErrorCode::kInternal, "backup copy failed its integrity check: " + report.integrity);
  SyncPath(partial.path, false);
  fs::rename(partial.path, dest_path, ec);
  if (ec) throw Error(ErrorCode::kInternal, "backup: cannot rename " + partial.path + ": " + ec.message());
  partial.keep = true;
  SyncPath(parent.empty() ? std::string(".") : parent.string(), true);
  report.file = fs::absolute(dest_path).lexically_normal().string();
  report.bytes = static_cast<std::int64_t>(fs::file_size(dest_path));
  report.duration_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace anchordb::storage
