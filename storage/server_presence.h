#pragma once
// Which anchordb servers are running on this database (issue 31: several servers on one database). On PostgreSQL a
// server holds a session-level advisory lock keyed by its id on a connection of its own; PostgreSQL releases it when
// that session ends (the server stopped, crashed or lost its connection), so "is server X running?" is "is X's lock
// held?", answered by the database itself, never by a clock. On SQLite one server has the file: every other id is
// gone. Not thread-safe: one owner calls it (the job service's worker).
#include <cstdint>
#include <memory>
#include <string>

#include "storage/connection.h"

namespace anchordb::storage {

class ServerPresence {
 public:
  // Takes an id of the form "<hex>" no other running server holds, starting from `seed` (e.g. a hash of host, pid and
  // start time). PostgreSQL: opens its connection and takes the lock; throws kUnavailable when it cannot.
  ServerPresence(const std::string& location, const ConnectionOptions& options, std::uint64_t seed);
  ~ServerPresence();
  ServerPresence(const ServerPresence&) = delete;
  ServerPresence& operator=(const ServerPresence&) = delete;

  const std::string& id() const { return id_; }
  // True when the server `other` holds its presence now (this server's own id: true). A row without a server id
  // (written before migration 0030) is nobody's: false. Throws kUnavailable when the database cannot answer.
  bool Running(const std::string& other);
  // PostgreSQL: takes the lock again when its session was lost (a failover, a restarted server); false when another
  // session holds it meanwhile (a server that took this id while this one was away). SQLite: true.
  bool Hold();

 private:
  bool TryLock(std::int64_t key);
  void Unlock(std::int64_t key);

  std::string id_;
  std::int64_t key_ = 0;
  std::unique_ptr<Connection> connection_;  // PostgreSQL only
};

}  // namespace anchordb::storage
