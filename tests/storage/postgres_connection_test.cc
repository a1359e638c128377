// The PostgreSQL engine of the storage seam (storage/postgres.h) against a real PostgreSQL 15 started by
// scripts/pg-scratch on a free loopback port: typed binds and reads, insert ids, transactions and snapshots, and the
// error kinds the SQLite engine gives for the same failures (issue 30).
#include "storage/postgres.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <functional>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <thread>

#include "schema/error.h"
#include "storage/connection.h"
#include "tests/support/pg_scratch.h"
#include "tests/support/error_of.h"

namespace anchordb::storage {
namespace postgres_connection_test {

using testing::CodeOf;

// This suite stops and restarts its server: it has one of its own (tests/support/pg_scratch.h), not the shared one.
using ScratchServer = testing::PgScratch;

class PostgresConnectionTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { server_ = std::make_unique<ScratchServer>(); }
  static void TearDownTestSuite() { server_.reset(); }
  void SetUp() override {
    c_ = OpenConnection(server_->Uri(), {});
    c_->Exec("DROP SCHEMA IF EXISTS t CASCADE; CREATE SCHEMA t; SET search_path = t");
  }


  static std::unique_ptr<ScratchServer> server_;
  std::unique_ptr<Connection> c_;
};
std::unique_ptr<ScratchServer> PostgresConnectionTest::server_;

TEST(PostgresPlaceholders, NumberPlainAndNumberedMarksOutsideQuotedText) {
  const auto [sql, count] = PostgresPlaceholders("SELECT '?', \"a?\", ?, ?3, ? WHERE x = ?2");
  EXPECT_EQ(sql, "SELECT '?', \"a?\", $1, $3, $4 WHERE x = $2");
  EXPECT_EQ(count, 4);
  EXPECT_TRUE(IsPostgresUri("postgresql://u@h/db"));
  EXPECT_TRUE(IsPostgresUri("postgres://h/db"));
  EXPECT_FALSE(IsPostgresUri("var/anchordb.sqlite"));
}

TEST_F(PostgresConnectionTest, EveryTypeRoundTripsExactlyAndInsertsAnswerTheirId) {
  EXPECT_EQ(c_->engine(), Engine::kPostgresql);
  c_->Exec("CREATE TABLE v (id bigserial PRIMARY KEY, i bigint, d double precision, s text, b bytea, n bigint)");
  std::string all_bytes;
  for (int k = 0; k < 256; ++k) all_bytes += static_cast<char>(k);
  const std::string text = "it's \"quoted\", ?, $1, \xc3\xa4";
  const std::int64_t first = Statement(*c_, "INSERT INTO v (i, d, s, b, n) VALUES (?, ?, ?, ?, ?) RETURNING id")
                                 .Bind(1, std::int64_t{-9223372036854775807LL - 1}).Bind(2, 0.1).Bind(3, text)
                                 .BindBlob(4, all_bytes).BindNull(5).RunReturningId();
  const std::int64_t second = Statement(*c_, "INSERT INTO v (i, d, s, b, n) VALUES (?, ?, ?, ?, ?) RETURNING id")
                                  .Bind(1, std::int64_t{9223372036854775807LL}).Bind(2, -1e-300).Bind(3, std::string())
                                  .BindBlob(4, std::string()).Bind(5, std::int64_t{7}).RunReturningId();
  EXPECT_EQ(second, first + 1);
  Statement s(*c_, "SELECT i, d, s, b, n FROM v ORDER BY id");
  ASSERT_TRUE(s.Step());
  EXPECT_EQ(s.Int(0), -9223372036854775807LL - 1);
  EXPECT_EQ(s.Double(1), 0.1);
  EXPECT_EQ(s.Text(2), text);
  EXPECT_EQ(s.Blob(3), all_bytes);
  EXPECT_TRUE(s.IsNull(4));
  ASSERT_TRUE(s.Step());
  EXPECT_EQ(s.Int(0), 9223372036854775807LL);
  EXPECT_EQ(s.Double(1), -1e-300);
  EXPECT_EQ(s.Text(2), "");
  EXPECT_EQ(s.Blob(3), "");
  EXPECT_EQ(s.Int(4), 7);
  EXPECT_FALSE(s.Step());
  Statement(*c_, "UPDATE v SET n = ?1 WHERE id >= ?2").Bind(1, std::int64_t{3}).Bind(2, first).Run();
  EXPECT_EQ(c_->Changes(), 2);
}

TEST_F(PostgresConnectionTest, ConstraintViolationsHaveTheKindsOfSqlite) {
  c_->Exec("CREATE TABLE p (id bigint PRIMARY KEY, x bigint NOT NULL CHECK (x >= 0)); "
           "CREATE TABLE k (p bigint REFERENCES p (id))");
  Statement(*c_, "INSERT INTO p VALUES (1, 1)").Run();
  EXPECT_EQ(CodeOf([&] { Statement(*c_, "INSERT INTO p VALUES (1, 2)").Run(); }), ErrorCode::kConflict);
  EXPECT_EQ(CodeOf([&] { Statement(*c_, "INSERT INTO k VALUES (?)").Bind(1, std::int64_t{9}).Run(); }),
            ErrorCode::kConflict);
  EXPECT_EQ(CodeOf([&] { Statement(*c_, "INSERT INTO p VALUES (2, -1)").Run(); }), ErrorCode::kInternal);
  EXPECT_EQ(CodeOf([&] { Statement(*c_, "INSERT INTO p (id, x) VALUES (3, ?)").BindNull(1).Run(); }), ErrorCode::kInternal);
  Statement count(*c_, "SELECT count(*) FROM p");
  ASSERT_TRUE(count.Step());
  EXPECT_EQ(count.Int(0), 1);  // none of the failed statements left a row
}

TEST_F(PostgresConnectionTest, AWriteIsUndoneUnlessCommittedAndAReadSeesOneSnapshot) {
  c_->Exec("CREATE TABLE r (x bigint)");
  {
    Transaction tx(*c_);
    Statement(*c_, "INSERT INTO r VALUES (1)").Run();
    EXPECT_TRUE(c_->InTransaction());
  }
  EXPECT_FALSE(c_->InTransaction());
  {
    Transaction tx(*c_);
    Statement(*c_, "INSERT INTO r VALUES (2)").Run();
    tx.Commit();
  }
  const auto other = OpenConnection(server_->Uri(), {});
  other->Exec("SET search_path = t");
  const auto count = [&](Connection& c) {
    Statement s(c, "SELECT count(*), coalesce(sum(x), 0) FROM r");
    s.Step();
    return std::make_pair(s.Int(0), s.Int(1));
  };
  EXPECT_EQ(count(*other), std::make_pair(std::int64_t{1}, std::int64_t{2}));
  {
    ReadTransaction snapshot(*other);
    EXPECT_EQ(count(*other).first, 1);
    Statement(*c_, "INSERT INTO r VALUES (3)").Run();  // autocommit, while the snapshot is open
    EXPECT_EQ(count(*other).first, 1);
    EXPECT_EQ(CodeOf([&] { Statement(*other, "INSERT INTO r VALUES (4)").Run(); }), ErrorCode::kUnavailable)
        << "a read transaction is read only (SQLSTATE 25006)";
  }
  EXPECT_EQ(count(*other).first, 2);
}

TEST_F(PostgresConnectionTest, AStatementTimeoutAndAnInterruptAreOverloadNotABug) {
  c_->Exec("SET statement_timeout = 50");
  EXPECT_EQ(CodeOf([&] { Statement(*c_, "SELECT pg_sleep(30)").Run(); }), ErrorCode::kOverloaded);
  c_->Exec("SET statement_timeout = 0");
  const auto watcher = OpenConnection(server_->Uri(), {});
  ErrorCode seen = ErrorCode::kInternal;
  std::thread sleeper([&] { seen = CodeOf([&] { Statement(*c_, "SELECT pg_sleep(60) /* interrupt me */").Run(); }); });
  for (int attempt = 0; attempt < 600; ++attempt) {  // until the server runs it (bounded; the sleep is 60 s)
    Statement s(*watcher, "SELECT count(*) FROM pg_stat_activity WHERE query LIKE '%interrupt me%' AND state = 'active' "
                          "AND pid <> pg_backend_pid()");
    s.Step();
    if (s.Int(0) == 1) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  c_->Interrupt();
  sleeper.join();
  EXPECT_EQ(seen, ErrorCode::kOverloaded);
  Statement after(*c_, "SELECT 1");  // the connection serves the next statement
  ASSERT_TRUE(after.Step());
  EXPECT_EQ(after.Int(0), 1);
}

TEST_F(PostgresConnectionTest, AStoppedServerIsUnavailableAndTheConnectionComesBackWithIt) {
  c_->Exec("CREATE TABLE d (x bigint)");
  Statement(*c_, "INSERT INTO d VALUES (?)").Bind(1, std::int64_t{1}).Run();
  ASSERT_EQ(server_->PgCtl("-m immediate stop"), 0);
  EXPECT_EQ(CodeOf([&] { Statement(*c_, "INSERT INTO d VALUES (2)").Run(); }), ErrorCode::kUnavailable);
  EXPECT_EQ(CodeOf([&] { Statement(*c_, "SELECT 1").Run(); }), ErrorCode::kUnavailable);  // still down
  ASSERT_EQ(server_->PgCtl(server_->StartOptions() + " start"), 0);
  c_->Exec("SET search_path = t");  // a new session
  Statement s(*c_, "SELECT count(*), sum(x) FROM d");
  ASSERT_TRUE(s.Step());
  EXPECT_EQ(s.Int(0), 1);  // the committed row is there, the failed one is not
  EXPECT_EQ(s.Int(1), 1);
}

TEST(PostgresConnection, NoServerAtTheAddressIsUnavailable) {
  try {
    // Port 1 on loopback: nothing listens there (and nothing may: it is privileged).
    OpenConnection("postgresql://nobody@127.0.0.1:1/db?connect_timeout=5&sslmode=disable&gssencmode=disable", {});
    ADD_FAILURE() << "connected";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kUnavailable);
    EXPECT_NE(std::string(e.what()).find("retry later"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace anchordb::storage
