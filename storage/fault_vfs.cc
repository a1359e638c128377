#include "storage/fault_vfs.h"

#include <sqlite3.h>

#include <atomic>
#include <mutex>

#include "schema/error.h"

namespace anchordb::storage::fault {
namespace {

// The plan, read on every I/O call and allocation: atomics, no lock.
std::atomic<int> g_kind{static_cast<int>(FaultKind::kNone)};
std::atomic<std::int64_t> g_nth{1};
std::atomic<std::int64_t> g_budget_bytes{0};
std::atomic<std::int64_t> g_count{0};
std::atomic<bool> g_fired{false};

bool Armed(FaultKind kind) { return g_kind.load(std::memory_order_acquire) == static_cast<int>(kind); }

// Counts one call of an armed kind; true when this call fails: I/O from the Nth call on, an allocation only the Nth.
bool CountCall(FaultKind kind) {
  if (!Armed(kind)) return false;
  const std::int64_t call = g_count.fetch_add(1) + 1, nth = g_nth.load();
  if (kind == FaultKind::kAllocation ? call != nth : call < nth) return false;
  g_fired = true;
  return true;
}

bool DiskFull(int bytes) {
  if (!Armed(FaultKind::kDiskFull)) return false;
  if (g_fired) return true;  // a full disk stays full until the fault clears
  if (g_count.fetch_add(bytes) + bytes <= g_budget_bytes.load()) return false;
  g_count.fetch_sub(bytes);  // not written
  g_fired = true;
  return true;
}

// ---- the VFS shim: every call delegates to the wrapped VFS; xWrite and xSync may fail first ----

sqlite3_vfs* g_real = nullptr;
sqlite3_vfs g_vfs{};

struct FaultFile {
  sqlite3_file base;
  sqlite3_file* real;  // the wrapped VFS's file, allocated right after this struct
};

sqlite3_file* Real(sqlite3_file* f) { return reinterpret_cast<FaultFile*>(f)->real; }

int Close(sqlite3_file* f) { return Real(f)->pMethods->xClose(Real(f)); }
int Read(sqlite3_file* f, void* buf, int n, sqlite3_int64 offset) { return Real(f)->pMethods->xRead(Real(f), buf, n, offset); }
int Write(sqlite3_file* f, const void* buf, int n, sqlite3_int64 offset) {
  if (CountCall(FaultKind::kWrite)) return SQLITE_IOERR_WRITE;
  if (DiskFull(n)) return SQLITE_FULL;
  return Real(f)->pMethods->xWrite(Real(f), buf, n, offset);
}
int Truncate(sqlite3_file* f, sqlite3_int64 size) { return Real(f)->pMethods->xTruncate(Real(f), size); }
int Sync(sqlite3_file* f, int flags) {
  if (CountCall(FaultKind::kSync)) return SQLITE_IOERR_FSYNC;
  return Real(f)->pMethods->xSync(Real(f), flags);
}
int FileSize(sqlite3_file* f, sqlite3_int64* size) { return Real(f)->pMethods->xFileSize(Real(f), size); }
int Lock(sqlite3_file* f, int level) { return Real(f)->pMethods->xLock(Real(f), level); }
int Unlock(sqlite3_file* f, int level) { return Real(f)->pMethods->xUnlock(Real(f), level); }
int CheckReservedLock(sqlite3_file* f, int* out) { return Real(f)->pMethods->xCheckReservedLock(Real(f), out); }
int FileControl(sqlite3_file* f, int op, void* arg) { return Real(f)->pMethods->xFileControl(Real(f), op, arg); }
int SectorSize(sqlite3_file* f) { return Real(f)->pMethods->xSectorSize(Real(f)); }
int DeviceCharacteristics(sqlite3_file* f) { return Real(f)->pMethods->xDeviceCharacteristics(Real(f)); }
int ShmMap(sqlite3_file* f, int region, int size, int extend, void volatile** out) {
  return Real(f)->pMethods->xShmMap(Real(f), region, size, extend, out);
}
int ShmLock(sqlite3_file* f, int offset, int n, int flags) { return Real(f)->pMethods->xShmLock(Real(f), offset, n, flags); }
void ShmBarrier(sqlite3_file* f) { Real(f)->pMethods->xShmBarrier(Real(f)); }
int ShmUnmap(sqlite3_file* f, int delete_flag) { return Real(f)->pMethods->xShmUnmap(Real(f), delete_flag); }
int Fetch(sqlite3_file* f, sqlite3_int64 offset, int n, void** out) { return Real(f)->pMethods->xFetch(Real(f), offset, n, out); }
int Unfetch(sqlite3_file* f, sqlite3_int64 offset, void* p) { return Real(f)->pMethods->xUnfetch(Real(f), offset, p); }

// Two method tables: one for files whose real methods have the shared-memory and mmap calls (version >= 3, the
// unix VFS's database and WAL files), one without them, so SQLite sees exactly what the wrapped file offers.
const sqlite3_io_methods kMethodsV3 = {3,        Close,   Read,    Write,      Truncate,          Sync,
                                       FileSize, Lock,    Unlock,  CheckReservedLock, FileControl,       SectorSize,
                                       DeviceCharacteristics, ShmMap, ShmLock, ShmBarrier, ShmUnmap, Fetch, Unfetch};
const sqlite3_io_methods kMethodsV1 = {1,        Close,   Read,    Write,      Truncate,          Sync,
                                       FileSize, Lock,    Unlock,  CheckReservedLock, FileControl,       SectorSize,
                                       DeviceCharacteristics, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr};

int Open(sqlite3_vfs*, sqlite3_filename name, sqlite3_file* file, int flags, int* out_flags) {
  auto* f = reinterpret_cast<FaultFile*>(file);
  f->real = reinterpret_cast<sqlite3_file*>(f + 1);
  const int rc = g_real->xOpen(g_real, name, f->real, flags, out_flags);
  if (rc != SQLITE_OK || !f->real->pMethods) {
    f->base.pMethods = nullptr;  // SQLite calls no method of a file that failed to open
    return rc;
  }
  f->base.pMethods = f->real->pMethods->iVersion >= 3 ? &kMethodsV3 : &kMethodsV1;
  return SQLITE_OK;
}

int Delete(sqlite3_vfs*, const char* name, int sync_dir) { return g_real->xDelete(g_real, name, sync_dir); }
int Access(sqlite3_vfs*, const char* name, int flags, int* out) { return g_real->xAccess(g_real, name, flags, out); }
int FullPathname(sqlite3_vfs*, const char* name, int n, char* out) { return g_real->xFullPathname(g_real, name, n, out); }
void* DlOpen(sqlite3_vfs*, const char* name) { return g_real->xDlOpen(g_real, name); }
void DlError(sqlite3_vfs*, int n, char* out) { g_real->xDlError(g_real, n, out); }
void (*DlSym(sqlite3_vfs*, void* handle, const char* symbol))(void) { return g_real->xDlSym(g_real, handle, symbol); }
void DlClose(sqlite3_vfs*, void* handle) { g_real->xDlClose(g_real, handle); }
int Randomness(sqlite3_vfs*, int n, char* out) { return g_real->xRandomness(g_real, n, out); }
int Sleep(sqlite3_vfs*, int us) { return g_real->xSleep(g_real, us); }
int CurrentTime(sqlite3_vfs*, double* out) { return g_real->xCurrentTime(g_real, out); }
int GetLastError(sqlite3_vfs*, int n, char* out) { return g_real->xGetLastError ? g_real->xGetLastError(g_real, n, out) : 0; }
int CurrentTimeInt64(sqlite3_vfs*, sqlite3_int64* out) { return g_real->xCurrentTimeInt64(g_real, out); }
int SetSystemCall(sqlite3_vfs*, const char* name, sqlite3_syscall_ptr p) { return g_real->xSetSystemCall(g_real, name, p); }
sqlite3_syscall_ptr GetSystemCall(sqlite3_vfs*, const char* name) { return g_real->xGetSystemCall(g_real, name); }
const char* NextSystemCall(sqlite3_vfs*, const char* name) { return g_real->xNextSystemCall(g_real, name); }

// ---- the allocation hook ----

sqlite3_mem_methods g_default_mem{};

void* Malloc(int n) { return CountCall(FaultKind::kAllocation) ? nullptr : g_default_mem.xMalloc(n); }
void Free(void* p) { g_default_mem.xFree(p); }
void* Realloc(void* p, int n) { return CountCall(FaultKind::kAllocation) ? nullptr : g_default_mem.xRealloc(p, n); }
int Size(void* p) { return g_default_mem.xSize(p); }
int Roundup(int n) { return g_default_mem.xRoundup(n); }
int Init(void*) { return g_default_mem.xInit(g_default_mem.pAppData); }
void Shutdown(void*) { g_default_mem.xShutdown(g_default_mem.pAppData); }

std::mutex g_install_mutex;

}  // namespace

const char* FaultKindName(FaultKind kind) {
  switch (kind) {
    case FaultKind::kNone: return "none";
    case FaultKind::kWrite: return "write";
    case FaultKind::kSync: return "sync";
    case FaultKind::kDiskFull: return "disk_full";
    case FaultKind::kAllocation: return "allocation";
  }
  return "none";
}

std::string RegisterFaultVfs(bool make_default) {
  std::lock_guard<std::mutex> lock(g_install_mutex);
  if (sqlite3_initialize() != SQLITE_OK) throw Error(ErrorCode::kInternal, "fault VFS: SQLite does not initialise");
  if (!g_real) {
    g_real = sqlite3_vfs_find(nullptr);
    if (!g_real) throw Error(ErrorCode::kInternal, "fault VFS: SQLite has no default VFS");
    g_vfs.iVersion = g_real->iVersion < 3 ? g_real->iVersion : 3;
    g_vfs.szOsFile = static_cast<int>(sizeof(FaultFile)) + g_real->szOsFile;
    g_vfs.mxPathname = g_real->mxPathname;
    g_vfs.zName = kFaultVfsName;
    g_vfs.xOpen = Open;
    g_vfs.xDelete = Delete;
    g_vfs.xAccess = Access;
    g_vfs.xFullPathname = FullPathname;
    g_vfs.xDlOpen = DlOpen;
    g_vfs.xDlError = DlError;
    g_vfs.xDlSym = DlSym;
    g_vfs.xDlClose = DlClose;
    g_vfs.xRandomness = Randomness;
    g_vfs.xSleep = Sleep;
    g_vfs.xCurrentTime = CurrentTime;
    g_vfs.xGetLastError = GetLastError;
    if (g_vfs.iVersion >= 2) g_vfs.xCurrentTimeInt64 = CurrentTimeInt64;
    if (g_vfs.iVersion >= 3) {
      g_vfs.xSetSystemCall = SetSystemCall;
      g_vfs.xGetSystemCall = GetSystemCall;
      g_vfs.xNextSystemCall = NextSystemCall;
    }
  }
  if (sqlite3_vfs_register(&g_vfs, make_default ? 1 : 0) != SQLITE_OK) {
    throw Error(ErrorCode::kInternal, "fault VFS: sqlite3_vfs_register failed");
  }
  return kFaultVfsName;
}

void InstallAllocationHook() {
  std::lock_guard<std::mutex> lock(g_install_mutex);
  if (g_default_mem.xMalloc) return;
  sqlite3_mem_methods current{};
  sqlite3_shutdown();  // SQLITE_CONFIG_* is accepted only while SQLite is not initialised
  if (sqlite3_config(SQLITE_CONFIG_GETMALLOC, &current) != SQLITE_OK) {
    throw Error(ErrorCode::kInternal, "allocation hook: SQLite refused SQLITE_CONFIG_GETMALLOC (a connection is open)");
  }
  g_default_mem = current;
  sqlite3_mem_methods hooked = current;
  hooked.xMalloc = Malloc;
  hooked.xFree = Free;
  hooked.xRealloc = Realloc;
  hooked.xSize = Size;
  hooked.xRoundup = Roundup;
  hooked.xInit = Init;
  hooked.xShutdown = Shutdown;
  if (sqlite3_config(SQLITE_CONFIG_MALLOC, &hooked) != SQLITE_OK) {
    g_default_mem = {};
    throw Error(ErrorCode::kInternal, "allocation hook: SQLite refused SQLITE_CONFIG_MALLOC");
  }
  sqlite3_config(SQLITE_CONFIG_MEMSTATUS, 0);  // as storage/sqlite.cc configures it
  if (sqlite3_initialize() != SQLITE_OK) throw Error(ErrorCode::kInternal, "allocation hook: SQLite does not initialise");
}

void Arm(const FaultPlan& plan) {
  g_kind.store(static_cast<int>(FaultKind::kNone), std::memory_order_release);
  g_count = 0;
  g_fired = false;
  g_nth = plan.nth < 1 ? 1 : plan.nth;
  g_budget_bytes = plan.budget_bytes < 0 ? 0 : plan.budget_bytes;
  g_kind.store(static_cast<int>(plan.kind), std::memory_order_release);
}

void Disarm() { g_kind.store(static_cast<int>(FaultKind::kNone), std::memory_order_release); }

bool Fired() { return g_fired; }

std::int64_t CallsCounted() { return g_count; }

}  // namespace anchordb::storage::fault
