// Migration 0017 on both engines: a scene model written by schema 0016 (camera, pose and parameters as JSON
// documents) reads back through the typed columns with the same numbers, a document that lacked a field takes the
// default the server applied, and a model written after the migration round-trips its typed record.
#include <gtest/gtest.h>

#include <vector>

#include "storage/connection.h"
#include "storage/migrations.h"
#include "storage/repositories.h"
#include "storage/scene_repository.h"
#include "tests/support/pg_scratch.h"

namespace anchordb::storage {
namespace {

class SceneDocumentsMigrationTest : public ::testing::TestWithParam<Engine> {
 protected:
  testing::TestDatabase db_{GetParam()};
};
INSTANTIATE_TEST_SUITE_P(Engines, SceneDocumentsMigrationTest, testing::BothEngines(), testing::EngineName);

std::vector<Migration> UpTo(Engine engine, int version) {
  std::vector<Migration> out;
  for (const Migration& m : EmbeddedMigrations(engine)) {
    if (m.version <= version) out.push_back(m);
  }
  return out;
}

std::int64_t InsertLegacyScene(Connection& c, const std::string& intrinsics, const std::string& pose, const std::string& params) {
  Statement s(c, "INSERT INTO scene_models (map_id, status, intrinsics, pose, x_m, y_m, z_m, params, started_ns) "
                 "VALUES ('home', 'closed', ?, ?, 1.25, -2.5, 0.75, ?, 1000) RETURNING id");
  s.Bind(1, intrinsics).Bind(2, pose).Bind(3, params);
  return s.RunReturningId();
}

TEST_P(SceneDocumentsMigrationTest, DocumentsOfSchema16BecomeTypedColumns) {
  const std::unique_ptr<Connection> c = OpenConnection(db_.location(), ConnectionOptions{});
  ApplyMigrations(*c, UpTo(GetParam(), 16));
  InsertMap(*c, {"home", "Home", 1});
  const std::int64_t full = InsertLegacyScene(
      *c, R"({"width":160,"height":120,"fx":140.25,"fy":141.5,"cx":79.5,"cy":59.5})",
      R"({"position":[1.25,-2.5,0.75],"orientation":[0.1,-0.2,0.3,0.9273618495495703]})",
      R"({"beta":0.05,"dynamic_mode":"subtract","depth_scale":5000})");
  const std::int64_t sparse = InsertLegacyScene(*c, R"({"width":8,"height":6,"fx":5,"fy":5,"cx":4,"cy":3})", "{}", "{}");
  const MigrationReport report = ApplyMigrations(*c, EmbeddedMigrations(GetParam()));
  ASSERT_EQ(report.applied.size(), EmbeddedMigrations(GetParam()).size() - UpTo(GetParam(), 16).size());

  const std::optional<SceneRecord> a = FindScene(*c, "home", full, false);
  ASSERT_TRUE(a.has_value());
  EXPECT_EQ(a->camera, (PinholeIntrinsics{160, 120, 140.25, 141.5, 79.5, 59.5}));
  EXPECT_EQ(a->pose.position_m, Eigen::Vector3d(1.25, -2.5, 0.75));
  EXPECT_EQ(a->pose.orientation.coeffs(), Eigen::Vector4d(0.1, -0.2, 0.3, 0.9273618495495703));  // x, y, z, w
  EXPECT_EQ(a->beta, 0.05);
  EXPECT_EQ(a->dynamic_mode, "subtract");
  EXPECT_EQ(a->depth_scale, 5000.0);

  const std::optional<SceneRecord> b = FindScene(*c, "home", sparse, false);
  ASSERT_TRUE(b.has_value());
  EXPECT_EQ(b->camera, (PinholeIntrinsics{8, 6, 5, 5, 4, 3}));
  EXPECT_EQ(b->pose.orientation.coeffs(), Eigen::Vector4d(0, 0, 0, 1));
  EXPECT_EQ(b->beta, 0.03);
  EXPECT_EQ(b->dynamic_mode, "exclude");
  EXPECT_EQ(b->depth_scale, 1000.0);

  SceneRecord fresh;
  fresh.map_id = "home";
  fresh.camera = {640, 480, 525.5, 524.25, 319.5, 239.5};
  fresh.pose.position_m = {3.0, 4.0, 1.5};
  fresh.pose.orientation = Eigen::Quaterniond(0.5, 0.5, -0.5, 0.5);
  fresh.beta = 0.04;
  fresh.dynamic_mode = "subtract";
  fresh.depth_scale = 1000.0;
  fresh.started_ns = 2000;
  const std::optional<SceneRecord> back = FindScene(*c, "home", InsertScene(*c, fresh), false);
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->camera, fresh.camera);
  EXPECT_EQ(back->pose.position_m, fresh.pose.position_m);
  EXPECT_EQ(back->pose.orientation.coeffs(), fresh.pose.orientation.coeffs());
  EXPECT_EQ(back->beta, 0.04);
  EXPECT_EQ(back->dynamic_mode, "subtract");
}

TEST_P(SceneDocumentsMigrationTest, AnUnknownDynamicModeIsRefusedByTheSchema) {
  const std::unique_ptr<Connection> c = OpenConnection(db_.location(), ConnectionOptions{});
  ApplyMigrations(*c, EmbeddedMigrations(GetParam()));
  InsertMap(*c, {"home", "Home", 1});
  SceneRecord r;
  r.map_id = "home";
  r.dynamic_mode = "sometimes";
  EXPECT_THROW(InsertScene(*c, r), std::exception);
}

}  // namespace
}  // namespace anchordb::storage
