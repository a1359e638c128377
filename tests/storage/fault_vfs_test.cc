// The fault VFS and allocation hook under the store (storage/fault_vfs.h): each fault kind reaches Store::Write as
// its error kind (I/O and memory: kUnavailable, a full disk: kInsufficientStorage), the failed write leaves nothing,
// reads go on while the fault is armed, and the same store writes again once it clears. Real SQLite files.
#include "storage/fault_vfs.h"

#include <gtest/gtest.h>

#include "storage/store.h"
#include "tests/support/temp_dir.h"

namespace anchordb::storage {
namespace fault_vfs_test {

class FaultVfsTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    fault::InstallAllocationHook();
    fault::RegisterFaultVfs(false);
  }
  void SetUp() override {
    StoreOptions o;
    o.path = dir_.File("fault.sqlite");
    o.connection.vfs = fault::kFaultVfsName;
    store_ = std::make_unique<Store>(o);
    store_->Write([](Connection& c) { c.Exec("CREATE TABLE t (x BLOB)"); });
  }
  void TearDown() override { fault::Disarm(); }

  // Inserts one 64 KiB row; the error kind when it fails.
  std::optional<ErrorCode> InsertRow() {
    try {
      store_->Write([](Connection& c) { Statement(c, "INSERT INTO t VALUES (?)").BindBlob(1, std::string(65536, 'x')).Run(); });
      return std::nullopt;
    } catch (const Error& e) {
      return e.code();
    }
  }
  std::int64_t Rows() {
    return store_->Read([](Connection& c) {
      Statement s(c, "SELECT count(*) FROM t");
      s.Step();
      return s.Int(0);
    });
  }

  testing::TempDir dir_;
  std::unique_ptr<Store> store_;
};

TEST_F(FaultVfsTest, AFailedWriteIsUnavailableLeavesNothingAndTheStoreWritesAgain) {
  ASSERT_FALSE(InsertRow());
  fault::Arm({fault::FaultKind::kWrite, 1, 0});
  EXPECT_EQ(InsertRow(), ErrorCode::kUnavailable);
  EXPECT_TRUE(fault::Fired());
  EXPECT_EQ(Rows(), 1);  // reads go on while the disk fails
  EXPECT_EQ(InsertRow(), ErrorCode::kUnavailable);  // the fault persists until it clears
  fault::Disarm();
  EXPECT_FALSE(InsertRow());
  EXPECT_EQ(Rows(), 2);
  EXPECT_EQ(store_->IntegrityCheck(), "ok");
}

TEST_F(FaultVfsTest, AFailedSyncIsUnavailable) {
  fault::Arm({fault::FaultKind::kSync, 1, 0});
  EXPECT_EQ(InsertRow(), ErrorCode::kUnavailable);
  fault::Disarm();
  EXPECT_EQ(Rows(), 0);
  EXPECT_FALSE(InsertRow());
  EXPECT_EQ(Rows(), 1);
}

TEST_F(FaultVfsTest, AFullDiskIsInsufficientStorageAndSmallerWritesFitTheBudget) {
  fault::Arm({fault::FaultKind::kDiskFull, 1, 16 * 1024});  // less than the row
  EXPECT_EQ(InsertRow(), ErrorCode::kInsufficientStorage);
  EXPECT_GT(fault::CallsCounted(), 0);
  EXPECT_LE(fault::CallsCounted(), 16 * 1024);
  fault::Arm({fault::FaultKind::kDiskFull, 1, 1 << 20});  // room for it
  EXPECT_FALSE(InsertRow());
  EXPECT_FALSE(fault::Fired());
  fault::Disarm();
  EXPECT_EQ(Rows(), 1);
}

TEST_F(FaultVfsTest, EveryFailedAllocationIsUnavailableAndLeavesNothing) {
  std::int64_t n = 1;
  for (; n < 1000; ++n) {
    fault::Arm({fault::FaultKind::kAllocation, n, 0});
    const auto code = InsertRow();
    fault::Disarm();
    if (!code) {  // no allocation failed, or only one SQLite could do without
      EXPECT_EQ(Rows(), 1) << "N=" << n;
      break;
    }
    EXPECT_EQ(*code, ErrorCode::kUnavailable) << "N=" << n;
    ASSERT_EQ(Rows(), 0) << "N=" << n;
  }
  EXPECT_GT(n, 1);
  EXPECT_LT(n, 1000);
  EXPECT_EQ(store_->IntegrityCheck(), "ok");
}

}  // namespace
}  // namespace anchordb::storage
