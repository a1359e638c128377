#pragma once
// Fault injection for tests (SPEC §8, the way SQLite tests itself): a VFS shim over the default unix VFS that, when
// armed, fails the Nth write (xWrite -> SQLITE_IOERR_WRITE), the Nth sync (xSync -> SQLITE_IOERR_FSYNC), or every
// write beyond a byte budget (a full disk: SQLITE_FULL), and an allocation hook that fails the Nth allocation SQLite
// makes (SQLITE_CONFIG_MALLOC wrapper over the default allocator). The state is process-wide: one plan at a time.
// I/O faults are persistent (from the Nth call on, every write or sync fails until Disarm), like a failed disk; an
// allocation fault fails one allocation (any thread's), like a transient memory shortage.
// Nothing here is used by the server unless a test registers it; the production allocator and VFS are untouched.
#include <cstdint>
#include <string>

namespace anchordb::storage::fault {

enum class FaultKind { kNone, kWrite, kSync, kDiskFull, kAllocation };

// Stable name ("write", "sync", "disk_full", "allocation"), for test names and messages.
const char* FaultKindName(FaultKind kind);

struct FaultPlan {
  FaultKind kind = FaultKind::kNone;
  // kWrite / kSync / kAllocation: the 1-based index, counted from Arm, of the call that fails first.
  std::int64_t nth = 1;
  // kDiskFull: bytes xWrite may still write after Arm; a write that would go beyond fails with SQLITE_FULL.
  std::int64_t budget_bytes = 0;
};

// The name the shim is registered under (for sqlite3_open_v2's zVfs and ConnectionOptions::vfs).
inline constexpr const char* kFaultVfsName = "anchordb-fault";

// Registers the shim over the current default VFS (idempotent; thread-safe). `make_default` also makes it the
// process default, so connections opened without a VFS name (backups, job connections) go through it too.
// Returns kFaultVfsName. Throws anchordb::Error(kInternal) if SQLite refuses the registration.
std::string RegisterFaultVfs(bool make_default);

// Installs the allocation hook. SQLite accepts SQLITE_CONFIG_MALLOC only before sqlite3_initialize; when SQLite was
// initialised already this shuts it down first, so call it while no connection is open. Idempotent.
// Throws anchordb::Error(kInternal) when SQLite refuses (a connection is still open).
void InstallAllocationHook();

// Starts counting from zero under `plan` (replacing any earlier plan). kAllocation needs InstallAllocationHook.
void Arm(const FaultPlan& plan);
// Stops injecting; the counters keep their values until the next Arm.
void Disarm();

// Since the last Arm: whether a fault was injected, and the calls counted for the armed kind (writes, syncs,
// allocations, or bytes written).
bool Fired();
std::int64_t CallsCounted();

}  // namespace anchordb::storage::fault
