#include "storage/server_presence.h"

#include <charconv>
#include <cstdio>

#include "schema/error.h"

namespace anchordb::storage {
namespace {

// The advisory lock keys of server presence: "srvr" in the high 32 bits, the id in the low 32 (the writer lock of
// storage/postgres.cc is another key).
constexpr std::int64_t kPresenceSpace = std::int64_t{0x73727672} << 32;

std::string IdText(std::uint32_t id) {
  char buffer[16];
  std::snprintf(buffer, sizeof buffer, "%08x", id);
  return buffer;
}

// The key of an id this class gave out; -1 for any other text (it names no running server).
std::int64_t KeyOf(const std::string& id) {
  std::uint32_t v = 0;
  const char* end = id.data() + id.size();
  const auto [at, ec] = std::from_chars(id.data(), end, v, 16);
  if (id.size() != 8 || ec != std::errc() || at != end || id != IdText(v)) return -1;  // IdText's form only
  return kPresenceSpace | static_cast<std::int64_t>(v);
}

}  // namespace

ServerPresence::ServerPresence(const std::string& location, const ConnectionOptions& options, std::uint64_t seed) {
  auto candidate = static_cast<std::uint32_t>(seed ^ (seed >> 32));
  if (!IsPostgresUri(location)) {
    id_ = IdText(candidate);
    key_ = KeyOf(id_);
    return;
  }
  connection_ = OpenConnection(location, options);
  for (int attempt = 0; attempt < 64; ++attempt, candidate = candidate * 2654435761u + 1u) {
    const std::string id = IdText(candidate);
    if (TryLock(KeyOf(id))) {
      id_ = id;
      key_ = KeyOf(id);
      return;
    }
  }
  throw Error(ErrorCode::kUnavailable, "no free server id on this database after 64 attempts");
}

// The lock is released on this session before it closes: closing alone ends the session, but PostgreSQL releases
// the lock only when the backend has exited, a moment later, so another server asking right after a clean stop could
// still see this one running (the storage test found it).
ServerPresence::~ServerPresence() {
  if (!connection_) return;
  try {
    Unlock(key_);
  } catch (const std::exception&) {
    // the session is gone already, and its lock with it
  }
}

bool ServerPresence::TryLock(std::int64_t key) {
  Statement s(*connection_, "SELECT pg_try_advisory_lock(?)");
  s.Bind(1, key);
  return s.Step() && s.Int(0) != 0;
}

void ServerPresence::Unlock(std::int64_t key) {
  Statement s(*connection_, "SELECT pg_advisory_unlock(?)");
  s.Bind(1, key);
  s.Step();
}

bool ServerPresence::Running(const std::string& other) {
  if (other == id_) return true;
  const std::int64_t key = KeyOf(other);
  if (key < 0 || !connection_) return false;
  if (!TryLock(key)) return true;  // its session holds it
  Unlock(key);
  return false;
}

bool ServerPresence::Hold() {
  if (!connection_) return true;
  // A session's advisory locks stack: taking the lock again on the same session would hold it twice. Whether this
  // session still holds it is read from pg_locks.
  Statement held(*connection_, "SELECT count(*) FROM pg_locks WHERE locktype = 'advisory' AND pid = pg_backend_pid() "
                               "AND granted AND classid::bigint = ? AND objid::bigint = ? AND objsubid = 1");
  held.Bind(1, static_cast<std::int64_t>(static_cast<std::uint64_t>(key_) >> 32))
      .Bind(2, static_cast<std::int64_t>(static_cast<std::uint32_t>(key_)));
  if (held.Step() && held.Int(0) > 0) return true;
  return TryLock(key_);
}

}  // namespace anchordb::storage
