// Token secrets and their matching (server/auth.h): secrets carry their id, digests are compared in constant time,
// and secrets of the earlier form (no id part) still authenticate. Real SQLite files.
#include "server/auth.h"

#include <gtest/gtest.h>

#include "storage/audit_repository.h"
#include "storage/repositories.h"
#include "tests/support/temp_dir.h"

namespace anchordb::server {
namespace auth_test {

storage::StoreOptions OptionsFor(const std::string& path) {
  storage::StoreOptions o;
  o.path = path;
  return o;
}

TEST(AuthTest, ConstantTimeEqualsComparesWholeStrings) {
  EXPECT_TRUE(ConstantTimeEquals("abcdef", "abcdef"));
  EXPECT_FALSE(ConstantTimeEquals("abcdef", "abcdeg"));
  EXPECT_FALSE(ConstantTimeEquals("abcdef", "bbcdef"));
  EXPECT_FALSE(ConstantTimeEquals("abc", "abcdef"));
  EXPECT_TRUE(ConstantTimeEquals("", ""));
}

TEST(AuthTest, CreatedSecretAuthenticatesByItsIdAndIsAudited) {
  testing::TempDir dir;
  storage::Store store(OptionsFor(dir.File("db.sqlite")));
  const CreatedToken t = CreateToken(store, "writer");
  ASSERT_EQ(t.secret.size(), 45u);
  EXPECT_EQ("tok_" + t.secret.substr(4, 8), t.id);
  const auto found = Authenticate(store, t.secret);
  ASSERT_TRUE(found);
  EXPECT_EQ(found->id, t.id);
  EXPECT_EQ(found->role, "writer");
  std::string wrong = t.secret;
  wrong.back() = wrong.back() == '0' ? '1' : '0';
  EXPECT_FALSE(Authenticate(store, wrong));
  EXPECT_FALSE(Authenticate(store, "adb_00000000_" + t.secret.substr(13)));  // unknown id, right secret part
  const auto audit = store.Read([](storage::Connection& c) { return storage::ListAuditRecords(c, {}); });
  ASSERT_EQ(audit.size(), 1u);
  EXPECT_EQ(audit[0].action, "token.create");
  EXPECT_EQ(audit[0].actor, "cli");
  EXPECT_EQ(audit[0].resource, t.id);
  EXPECT_EQ(audit[0].after_json->find(t.secret), std::string::npos);
}

TEST(AuthTest, SecretOfTheEarlierFormStillAuthenticates) {
  testing::TempDir dir;
  storage::Store store(OptionsFor(dir.File("db.sqlite")));
  const std::string legacy = "adb_" + std::string(32, 'c');
  store.Write([&](storage::Connection& c) { storage::InsertToken(c, {"tok_old", Sha256Hex(legacy), "admin", 1}); });
  CreateToken(store, "reader");
  const auto found = Authenticate(store, legacy);
  ASSERT_TRUE(found);
  EXPECT_EQ(found->id, "tok_old");
  EXPECT_EQ(found->role, "admin");
  EXPECT_FALSE(Authenticate(store, "adb_" + std::string(32, 'd')));
  EXPECT_FALSE(Authenticate(store, ""));
}

TEST(AuthTest, UnknownRoleWritesNothing) {
  testing::TempDir dir;
  storage::Store store(OptionsFor(dir.File("db.sqlite")));
  EXPECT_THROW(CreateToken(store, "root"), std::invalid_argument);
  EXPECT_EQ(store.Read([](storage::Connection& c) { return storage::CountTokens(c); }), 0);
  EXPECT_TRUE(store.Read([](storage::Connection& c) { return storage::ListAuditRecords(c, {}); }).empty());
}

}  // namespace
}  // namespace anchordb::server
