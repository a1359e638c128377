// Migration 0017 on both engines: a scene model written by schema 0016 (camera, pose and parameters as JSON
// documents) reads back through the typed columns with the same numbers, a document that lacked a field takes the
// default the server applied, and a model written after the migration round-trips its typed record. Migration 0018:
// the pose covariance of schema 0017 (a JSON array) reads as the same 36 numbers, and a new one is stored in the
// blob envelope, not as text. Migration 0021: a journalled frame's model_after of schema 20 reads as typed columns.
// Migration 0022: a merge report of schema 21 reads as typed columns and child rows; a new one round-trips.
#include <gtest/gtest.h>

#include <array>
#include <charconv>
#include <cmath>
#include <vector>

#include "storage/connection.h"
#include "storage/frame_journal.h"
#include "storage/migrations.h"
#include "storage/repositories.h"
#include "storage/scene_repository.h"
#include "tests/support/pg_scratch.h"

namespace anchordb::storage {
namespace scene_documents_migration_test {

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

std::array<double, 36> SomeCovariance() {
  std::array<double, 36> c{};
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) c[i * 6 + j] = i == j ? 1e-4 * (i + 1) : -2.5e-7 * (i + j);
  }
  return c;
}

TEST_P(SceneDocumentsMigrationTest, ThePoseCovarianceOfSchema17ReadsAndANewOneIsAStoredArray) {
  const std::unique_ptr<Connection> c = OpenConnection(db_.location(), ConnectionOptions{});
  ApplyMigrations(*c, UpTo(GetParam(), 17));
  InsertMap(*c, {"home", "Home", 1});
  const std::array<double, 36> expected = SomeCovariance();
  std::string text = "[";
  for (std::size_t i = 0; i < expected.size(); ++i) {
    char number[32];
    const auto end = std::to_chars(number, number + sizeof number, expected[i]).ptr;
    text += (i ? (i % 2 ? ", " : ",") : "") + std::string(number, end);
  }
  text += "]";
  const auto legacy = [&](const std::string& covariance) {
    Statement s(*c, "INSERT INTO scene_models (map_id, status, x_m, y_m, z_m, started_ns, pose_covariance) "
                    "VALUES ('home', 'closed', 0, 0, 0, 1, ?) "
                    "RETURNING id");
    s.Bind(1, covariance);
    return s.RunReturningId();
  };
  const std::int64_t written = legacy(text), truncated = legacy("[1.0, 2.0]"), garbage = legacy("{\"a\": 1}");
  ApplyMigrations(*c, EmbeddedMigrations(GetParam()));

  const std::optional<SceneRecord> a = FindScene(*c, "home", written, false);
  ASSERT_TRUE(a.has_value());
  ASSERT_TRUE(a->pose_covariance.has_value());
  EXPECT_EQ(*a->pose_covariance, expected);
  EXPECT_FALSE(FindScene(*c, "home", truncated, false)->pose_covariance.has_value());
  EXPECT_FALSE(FindScene(*c, "home", garbage, false)->pose_covariance.has_value());

  SceneRecord fresh;
  fresh.map_id = "home";
  fresh.started_ns = 2;
  fresh.pose_covariance = expected;
  const std::int64_t id = InsertScene(*c, fresh);
  const std::optional<SceneRecord> back = FindScene(*c, "home", id, false);
  ASSERT_TRUE(back.has_value() && back->pose_covariance.has_value());
  EXPECT_EQ(*back->pose_covariance, expected);
  Statement columns(*c, "SELECT pose_covariance IS NULL, pose_covariance_f64 IS NOT NULL FROM scene_models WHERE id = ?");
  columns.Bind(1, id);
  ASSERT_TRUE(columns.Step());
  EXPECT_EQ(columns.Int(0), 1);  // no text
  EXPECT_EQ(columns.Int(1), 1);  // the envelope
  fresh.pose_covariance.reset();
  EXPECT_FALSE(FindScene(*c, "home", InsertScene(*c, fresh), false)->pose_covariance.has_value());
}

TEST_P(SceneDocumentsMigrationTest, TheModelAfterOfSchema20BecomesTypedColumns) {
  const std::unique_ptr<Connection> c = OpenConnection(db_.location(), ConnectionOptions{});
  ApplyMigrations(*c, UpTo(GetParam(), 20));
  InsertMap(*c, {"home", "Home", 1});
  Statement scene(*c, "INSERT INTO scene_models (map_id, status, x_m, y_m, z_m, started_ns) "
                     "VALUES ('home', 'observing', 0, 0, 1, 1) RETURNING id");
  const std::int64_t id = scene.RunReturningId();
  const auto legacy = [&](std::int64_t frame, const std::string& model_after) {
    Statement(*c, "INSERT INTO scene_frame_journal (scene_id, frame, stamp_ns, depth_codec, depth, depth_scale, "
                  "model_after) VALUES (?, ?, 5, 'png', ?, 1000, ?)")
        .Bind(1, id).Bind(2, frame).BindBlob(3, "png bytes").Bind(4, model_after).Run();
  };
  legacy(1, R"({"counts":{"supported":1200,"reset":30,"movable":45,"dynamic":6,"no_depth":700},)"
            R"("settle":{"movable_at_keyframe":40,"reset_since_keyframe":12,"previous_movable":-1,"stable_frames":3}})");
  legacy(2, R"({"counts":{"supported":5}})");  // what a document lacks takes the detector's initial state
  ApplyMigrations(*c, EmbeddedMigrations(GetParam()));

  const std::vector<JournalFrame> rows = ReadJournal(*c, id, 0);
  ASSERT_EQ(rows.size(), 2u);
  const JournalModelAfter& a = rows[0].model_after;
  EXPECT_EQ(a.supported_px, 1200);
  EXPECT_EQ(a.reset_px, 30);
  EXPECT_EQ(a.movable_px, 45);
  EXPECT_EQ(a.dynamic_px, 6);
  EXPECT_EQ(a.no_depth_px, 700);
  EXPECT_EQ(a.settle_movable_at_keyframe_px, 40);
  EXPECT_EQ(a.settle_reset_since_keyframe_px, 12);
  EXPECT_EQ(a.settle_previous_movable_px, -1);
  EXPECT_EQ(a.settle_stable_frames, 3);
  const JournalModelAfter& b = rows[1].model_after;
  EXPECT_EQ(b.supported_px, 5);
  EXPECT_EQ(b.movable_px, 0);
  EXPECT_EQ(b.settle_previous_movable_px, -1);
}

TEST_P(SceneDocumentsMigrationTest, TheMergeReportOfSchema21BecomesTypedColumnsAndChildRows) {
  const std::unique_ptr<Connection> c = OpenConnection(db_.location(), ConnectionOptions{});
  ApplyMigrations(*c, UpTo(GetParam(), 21));
  InsertMap(*c, {"home", "Home", 1});
  const auto legacy = [&](const std::string& report) {
    Statement s(*c, "INSERT INTO scene_models (map_id, status, x_m, y_m, z_m, started_ns, merge_report) "
                    "VALUES ('home', 'closed', 0, 0, 1, 5, ?) RETURNING id");
    s.Bind(1, report);
    return s.RunReturningId();
  };
  const std::int64_t merged = legacy(R"({
    "requested": true, "strategy": "naive", "performed": true, "pending": false,
    "candidates": [{"scene": 3, "overlap": 0.8125}, {"scene": 4, "overlap": null}],
    "models_used": [{"scene": 3,
      "icp": {"converged": true, "applied": false, "fitness_m2": null, "fitness_before_m2": 0.0123,
              "correction": {"translation_m": [0.01, -0.02, 0.003], "rotation_rad": 0.0174},
              "source_points": 1200, "target_points": 3400, "verdict": "ill-conditioned",
              "relative_information": [1, 0.5, 0.25, 0.125, 0.0625, 0.03125], "unobservable_directions": 2,
              "mahalanobis2": 4.5, "remaining_sigma": [0.01, 0.02, 0.03, 0.004, 0.005, 0.006]},
      "pixels": {"rasterised": 10, "supported": 9, "replaced_farther": 8, "rear_projected": 7, "filled_unknown": 6,
                 "rejected_fov": 5, "rejected_occlusion": 4, "rejected_neighbourhood": 3, "rejected_uncertain": 2},
      "premises": {"tolerance_px": 1.5, "tolerance_m": 0.02, "merged": true, "fallback": ""}}],
    "timing_ms": {"icp": 103.7, "rasterise": 5.0, "merge": 14.3},
    "superseded": [3, 4],
    "pose_corrected": {"position": [0.1, 0.2, 1.3], "orientation": [0.0, 0.0, 0.0499791692706783, 0.9987502603949663]},
    "pose_corrected_by_scene": 3})");
  const std::int64_t old = legacy(R"({"candidates": [], "models_used": [{"scene": 8, "icp": {"converged": true}}]})");
  const std::int64_t empty = legacy("{}");
  ApplyMigrations(*c, EmbeddedMigrations(GetParam()));

  const MergeReportRecord a = FindScene(*c, "home", merged, false)->merge_report;
  EXPECT_TRUE(a.requested);
  EXPECT_EQ(a.strategy, "naive");
  EXPECT_EQ(a.pending, std::optional<bool>(false));
  EXPECT_TRUE(a.performed);
  ASSERT_EQ(a.candidates.size(), 2u);
  EXPECT_EQ(a.candidates[0].scene_id, 3);
  EXPECT_EQ(a.candidates[0].overlap, 0.8125);
  EXPECT_TRUE(std::isnan(a.candidates[1].overlap));
  ASSERT_EQ(a.models_used.size(), 1u);
  const MergedModelRecord& m = a.models_used[0];
  EXPECT_EQ(m.scene_id, 3);
  EXPECT_TRUE(m.icp_converged);
  EXPECT_FALSE(m.icp_applied);
  EXPECT_TRUE(std::isnan(m.fitness_m2));
  EXPECT_EQ(m.fitness_before_m2, 0.0123);
  EXPECT_EQ(m.correction_translation_m, (std::array<double, 3>{0.01, -0.02, 0.003}));
  EXPECT_EQ(m.source_points, 1200);
  EXPECT_EQ(m.icp_verdict, "ill-conditioned");
  EXPECT_EQ(m.relative_information[5], 0.03125);
  EXPECT_EQ(m.unobservable_directions, 2);
  EXPECT_EQ(m.mahalanobis2, 4.5);
  EXPECT_EQ(m.remaining_sigma[3], 0.004);
  EXPECT_EQ(m.rear_projected_px, 7);
  EXPECT_EQ(m.rejected_uncertain_px, 2);
  EXPECT_EQ(m.tolerance_m, 0.02);
  EXPECT_EQ(a.icp_ms, 103.7);
  EXPECT_EQ(a.superseded, (std::vector<std::int64_t>{3, 4}));
  ASSERT_TRUE(a.pose_corrected.has_value());
  EXPECT_EQ((*a.pose_corrected)[2], 1.3);
  EXPECT_EQ((*a.pose_corrected)[6], 0.9987502603949663);
  EXPECT_EQ(a.corrected_by_scene, 3);

  // A report of an older release: what it lacks takes the defaults the server applied.
  const MergeReportRecord b = FindScene(*c, "home", old, false)->merge_report;
  EXPECT_TRUE(b.requested);
  EXPECT_EQ(b.strategy, "algorithm2");
  EXPECT_FALSE(b.pending.has_value());
  ASSERT_EQ(b.models_used.size(), 1u);
  EXPECT_EQ(b.models_used[0].correction_translation_m, (std::array<double, 3>{0, 0, 0}));
  EXPECT_TRUE(std::isnan(b.models_used[0].mahalanobis2));
  EXPECT_EQ(b.models_used[0].icp_verdict, "");
  const MergeReportRecord e = FindScene(*c, "home", empty, false)->merge_report;
  EXPECT_TRUE(e.candidates.empty() && e.models_used.empty() && e.superseded.empty());
  EXPECT_FALSE(e.pose_corrected.has_value());
  EXPECT_EQ(ListScenes(*c, "home", SceneFilter{}).size(), 3u);
}

TEST_P(SceneDocumentsMigrationTest, AMergeReportRoundTripsAndACheckpointReplacesItsLists) {
  const std::unique_ptr<Connection> c = OpenConnection(db_.location(), ConnectionOptions{});
  ApplyMigrations(*c, EmbeddedMigrations(GetParam()));
  InsertMap(*c, {"home", "Home", 1});
  SceneRecord r;
  r.map_id = "home";
  r.started_ns = 1;
  r.merge_report.candidates = {{11, 0.5}, {12, std::nan("")}};
  r.merge_report.pending = true;
  r.id = InsertScene(*c, r);
  MergeReportRecord opened = FindScene(*c, "home", r.id, false)->merge_report;
  ASSERT_EQ(opened.candidates.size(), 2u);
  EXPECT_TRUE(std::isnan(opened.candidates[1].overlap));
  EXPECT_EQ(opened.pending, std::optional<bool>(true));
  EXPECT_FALSE(opened.performed);

  r.merge_report.performed = true;
  r.merge_report.pending = false;
  MergedModelRecord m;
  m.scene_id = 11;
  m.fitness_m2 = 0.004;
  m.fallback = "no overlap";
  r.merge_report.models_used = {m};
  r.merge_report.superseded = {11};
  r.merge_report.pose_corrected = std::array<double, 7>{1, 2, 3, 0, 0, 0, 1};
  r.state_version = 1;
  UpdateSceneState(*c, r, 0);
  const MergeReportRecord after = FindScene(*c, "home", r.id, false)->merge_report;
  EXPECT_TRUE(after.performed);
  EXPECT_EQ(after.candidates.size(), 2u);
  ASSERT_EQ(after.models_used.size(), 1u);
  EXPECT_EQ(after.models_used[0].fallback, "no overlap");
  EXPECT_EQ(after.superseded, (std::vector<std::int64_t>{11}));
  ASSERT_TRUE(after.pose_corrected.has_value());
  EXPECT_EQ((*after.pose_corrected)[6], 1.0);
  r.state_version = 2;
  UpdateSceneState(*c, r, 1);  // a later checkpoint leaves the lists as they were
  EXPECT_EQ(FindScene(*c, "home", r.id, false)->merge_report.candidates.size(), 2u);
  Statement rows(*c, "SELECT count(*) FROM scene_merge_candidates");
  ASSERT_TRUE(rows.Step());
  EXPECT_EQ(rows.Int(0), 2);
}

}  // namespace
}  // namespace anchordb::storage
