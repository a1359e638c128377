// Migration 0025 on both engines: the evidence of a perceived piece of furniture written by schema 24 (a JSON array
// of keyframe ids) reads back as the same ids, ascending and each once; entries that were not integers are left out
// as the server of schema 24 left them out, and a column that held no array gives no evidence.
#include <gtest/gtest.h>

#include <vector>

#include "storage/connection.h"
#include "storage/event_repository.h"
#include "storage/furniture_instance_repository.h"
#include "storage/migrations.h"
#include "storage/repositories.h"
#include "tests/support/pg_scratch.h"

namespace anchordb::storage {
namespace furniture_evidence_migration_test {

class FurnitureEvidenceMigrationTest : public ::testing::TestWithParam<Engine> {
 protected:
  testing::TestDatabase db_{GetParam()};
};
INSTANTIATE_TEST_SUITE_P(Engines, FurnitureEvidenceMigrationTest, testing::BothEngines(), testing::EngineName);

std::vector<Migration> UpTo(Engine engine, int version) {
  std::vector<Migration> out;
  for (const Migration& m : EmbeddedMigrations(engine)) {
    if (m.version <= version) out.push_back(m);
  }
  return out;
}

std::int64_t InsertLegacyPiece(Connection& c, const std::string& evidence_json) {
  InstanceRecord instance;
  instance.map_id = "home";
  instance.kind = "furniture";
  instance.created_ns = instance.updated_ns = instance.last_seen_ns = 5;
  const std::int64_t id = InsertInstance(c, instance);
  Statement s(c, "INSERT INTO furniture_instances (instance_id, map_id, classifier, min_z_m, height_m, observations, "
                 "evidence_json, cloud, created_ns, updated_ns) VALUES (?, 'home', 'geometry', 0, 0.7, 2, ?, ?, 1, 2)");
  s.Bind(1, id).Bind(2, evidence_json).BindBlob(3, std::string()).Run();
  return id;
}

TEST_P(FurnitureEvidenceMigrationTest, EvidenceArraysOfSchema24BecomeRows) {
  const std::unique_ptr<Connection> c = OpenConnection(db_.location(), ConnectionOptions{});
  ApplyMigrations(*c, UpTo(GetParam(), 24));
  InsertMap(*c, {"home", "Home", 1});
  const std::int64_t seen = InsertLegacyPiece(*c, R"([12, 3, 3, "x", 2.5, null, 7])");
  const std::int64_t none = InsertLegacyPiece(*c, "[]");
  const std::int64_t broken = InsertLegacyPiece(*c, "not json");
  const std::int64_t object = InsertLegacyPiece(*c, R"({"3": 4})");
  ApplyMigrations(*c, EmbeddedMigrations(GetParam()));

  const auto evidence = [&](std::int64_t id) {
    const auto piece = FindFurnitureInstance(*c, "home", id, false);
    EXPECT_TRUE(piece.has_value()) << id;
    return piece ? piece->evidence_keyframes : std::vector<std::int64_t>{-1};
  };
  EXPECT_EQ(evidence(seen), (std::vector<std::int64_t>{3, 7, 12}));
  EXPECT_TRUE(evidence(none).empty());
  EXPECT_TRUE(evidence(broken).empty());
  EXPECT_TRUE(evidence(object).empty());
  // The list gives each piece its own evidence; deleting a piece takes its rows.
  const auto listed = ListFurnitureInstances(*c, "home", false);
  ASSERT_EQ(listed.size(), 4u);
  EXPECT_EQ(listed.front().evidence_keyframes, (std::vector<std::int64_t>{3, 7, 12}));
  Statement(*c, "DELETE FROM instances WHERE id = ?").Bind(1, seen).Run();
  Statement count(*c, "SELECT count(*) FROM furniture_instance_evidence");
  ASSERT_TRUE(count.Step());
  EXPECT_EQ(count.Int(0), 0);
}

}  // namespace
}  // namespace anchordb::storage
