// Migration 0026 on both engines: an instance's labels and a classification's distribution written by schema 25 as
// JSON objects read back as the same label -> weight maps from rows; entries whose value was not a number are left
// out (as the server of schema 25 left them out), text that is not an object gives no labels, and the lookups by
// label (instances?label=, with a classifier's shares) find what they found before.
#include <gtest/gtest.h>

#include <map>
#include <vector>

#include "storage/connection.h"
#include "storage/event_repository.h"
#include "storage/instance_classification_repository.h"
#include "storage/migrations.h"
#include "storage/repositories.h"
#include "tests/support/pg_scratch.h"

namespace anchordb::storage {
namespace instance_labels_migration_test {

using Labels = std::map<std::string, double>;

class InstanceLabelsMigrationTest : public ::testing::TestWithParam<Engine> {
 protected:
  testing::TestDatabase db_{GetParam()};
};
INSTANTIATE_TEST_SUITE_P(Engines, InstanceLabelsMigrationTest, testing::BothEngines(), testing::EngineName);

std::vector<Migration> UpTo(Engine engine, int version) {
  std::vector<Migration> out;
  for (const Migration& m : EmbeddedMigrations(engine)) {
    if (m.version <= version) out.push_back(m);
  }
  return out;
}

std::int64_t InsertLegacyInstance(Connection& c, const std::string& labels_json) {
  Statement s(c, "INSERT INTO instances (map_id, kind, status, labels, x_m, y_m, z_m, extent_x_m, extent_y_m, "
                 "extent_z_m, last_seen_ns, created_ns, updated_ns) "
                 "VALUES ('home', 'object', 'present', ?, 0, 0, 0, 0, 0, 0, 1, 1, 1) RETURNING id");
  s.Bind(1, labels_json);
  return s.RunReturningId();
}

void InsertLegacyClassification(Connection& c, std::int64_t instance_id, const std::string& distribution_json) {
  Statement s(c, "INSERT INTO instance_classifications (instance_id, map_id, classifier, label, distribution, stamp_ns) "
                 "VALUES (?, 'home', 'kitchen', 'cup', ?, 3)");
  s.Bind(1, instance_id).Bind(2, distribution_json).Run();
}

std::vector<std::int64_t> WithLabel(Connection& c, const std::string& label, bool from_classifier) {
  InstanceFilter f;
  f.label = label;
  f.label_from_classifier = from_classifier;
  std::vector<std::int64_t> ids;
  for (const auto& r : ListInstances(c, "home", f, false)) ids.push_back(r.id);
  return ids;
}

TEST_P(InstanceLabelsMigrationTest, LabelAndDistributionObjectsOfSchema25BecomeRows) {
  const std::unique_ptr<Connection> c = OpenConnection(db_.location(), ConnectionOptions{});
  ApplyMigrations(*c, UpTo(GetParam(), 25));
  InsertMap(*c, {"home", "Home", 1});
  const std::int64_t named = InsertLegacyInstance(*c, R"({"keys": 2, "wallet": 0.5, "note": "x", "flag": true})");
  const std::int64_t bare = InsertLegacyInstance(*c, "{}");
  const std::int64_t classified = InsertLegacyInstance(*c, "{}");
  InsertLegacyClassification(*c, classified, R"({"cup": 0.75, "mug": 0.25, "unknown": 0})");
  InsertLegacyClassification(*c, named, R"({"keys": 1})");
  // Schema 25's label triggers refused text that is not JSON on both engines, and any non-object on PostgreSQL
  // (jsonb_object_keys); SQLite's json_each kept an array (indexing its positions as labels).
  std::vector<std::int64_t> broken;
  if (GetParam() == Engine::kSqlite) broken = {InsertLegacyInstance(*c, "[1, 2]"), InsertLegacyInstance(*c, "[]")};
  InsertLegacyClassification(*c, bare, "not json");
  ApplyMigrations(*c, EmbeddedMigrations(GetParam()));

  const auto labels = [&](std::int64_t id) {
    const auto r = FindInstance(*c, "home", id, false);
    EXPECT_TRUE(r.has_value()) << id;
    return r ? r->labels : Labels{{"missing", -1}};
  };
  EXPECT_EQ(labels(named), (Labels{{"keys", 2.0}, {"wallet", 0.5}}));
  EXPECT_TRUE(labels(bare).empty());
  EXPECT_TRUE(labels(classified).empty());
  for (const std::int64_t id : broken) EXPECT_TRUE(labels(id).empty()) << id;

  const auto distribution = [&](std::int64_t id) {
    const auto k = FindInstanceClassification(*c, "home", id);
    EXPECT_TRUE(k.has_value()) << id;
    return k ? k->distribution : Labels{{"missing", -1}};
  };
  EXPECT_EQ(distribution(classified), (Labels{{"cup", 0.75}, {"mug", 0.25}, {"unknown", 0.0}}));
  EXPECT_EQ(distribution(named), (Labels{{"keys", 1.0}}));
  EXPECT_TRUE(distribution(bare).empty());

  // By label: people's labels; with the classifier, also an instance nobody named whose classification gives the
  // label a share above 0 -- not the rejection class, not a named instance's classification.
  EXPECT_EQ(WithLabel(*c, "keys", false), std::vector<std::int64_t>{named});
  EXPECT_TRUE(WithLabel(*c, "cup", false).empty());
  EXPECT_EQ(WithLabel(*c, "cup", true), std::vector<std::int64_t>{classified});
  EXPECT_EQ(WithLabel(*c, "mug", true), std::vector<std::int64_t>{classified});
  EXPECT_TRUE(WithLabel(*c, "unknown", true).empty());
  EXPECT_EQ(WithLabel(*c, "keys", true), std::vector<std::int64_t>{named});

  // Writes after the migration keep the rows: a relabel replaces them, deleting the instance takes them.
  auto r = *FindInstance(*c, "home", named, false);
  r.labels = {{"purse", 1.0}};
  UpdateInstance(*c, r);
  EXPECT_EQ(labels(named), (Labels{{"purse", 1.0}}));
  EXPECT_TRUE(WithLabel(*c, "keys", false).empty());
  Statement(*c, "DELETE FROM instances WHERE id = ?").Bind(1, classified).Run();
  Statement shares(*c, "SELECT count(*) FROM instance_classification_shares WHERE instance_id = ?");
  shares.Bind(1, classified);
  ASSERT_TRUE(shares.Step());
  EXPECT_EQ(shares.Int(0), 0);
}

}  // namespace
}  // namespace anchordb::storage
