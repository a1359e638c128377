#pragma once
// Online backup of the whole database file with SQLite's backup API (SPEC §8): a consistent copy taken while the
// server keeps reading and writing. Pages are copied in steps (progress, interruption); when other connections
// write meanwhile SQLite restarts the copy, so after a few restarts the rest is copied in one step (one read
// transaction: consistent and finite whatever the write load). The copy is written to "<dest>.partial", checked with
// PRAGMA integrity_check, synced and only then renamed to `dest`: a crash never leaves a half copy under the final
// name. Restoring is serving the copy (or copying it over the database while the server is stopped).
#include <cstdint>
#include <functional>
#include <string>


namespace anchordb::storage {

struct BackupReport {
  std::string file;             // the finished copy
  std::int64_t bytes = 0;       // its size
  std::int64_t pages = 0;       // pages copied (of the snapshot that was copied)
  int restarts = 0;             // times writers made SQLite start the copy again
  std::string integrity;        // "ok" (else the copy is deleted and Backup throws)
  double duration_s = 0.0;
};

// Called between steps with the fraction copied; may throw to abort (the partial file is removed).
using BackupProgress = std::function<void(double fraction)>;

// Copies the database at `source_path` to `dest_path` (which must not exist; its directory is created).
// Throws anchordb::Error: kConflict if `dest_path` exists, kInternal on I/O errors, kInvalidArgument for a PostgreSQL
// location (the message names pg_basebackup and pg_dump: the server's own tools back it up).
BackupReport Backup(const std::string& source_path, const std::string& dest_path, int busy_timeout_ms,
                    const BackupProgress& progress = {}, int pages_per_step = 256);

// "<directory>/<stem>-YYYYMMDDTHHMMSSZ[-label].sqlite" for the database file `db_path` at `now_ns` (UTC).
std::string BackupFileName(const std::string& directory, const std::string& db_path, std::int64_t now_ns,
                           const std::string& label);

}  // namespace anchordb::storage
