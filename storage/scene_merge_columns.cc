#include "storage/scene_merge_columns.h"

#include <cmath>
#include <limits>

namespace anchordb::storage::merge_report {

const char* const kColumns =
    "merge_requested, merge_strategy, merge_pending, merge_performed, merge_icp_ms, merge_rasterise_ms, merge_merge_ms, "
    "corrected_x_m, corrected_y_m, corrected_z_m, corrected_qx, corrected_qy, corrected_qz, corrected_qw, "
    "corrected_by_scene, merge_list_rows";

namespace {

// The columns of scene_merge_models after scene_id and position, in the order ReadModel and BindModel take them.
constexpr const char* kModelColumns =
    "merged_scene, icp_converged, icp_applied, fitness_m2, fitness_before_m2, correction_x_m, "
    "correction_y_m, correction_z_m, correction_rotation_rad, source_points, target_points, icp_verdict, "
    "information_tx, information_ty, information_tz, information_rx, information_ry, information_rz, "
    "unobservable_directions, mahalanobis2, sigma_tx_m, sigma_ty_m, sigma_tz_m, sigma_rx_rad, "
    "sigma_ry_rad, sigma_rz_rad, rasterised_px, supported_px, replaced_farther_px, rear_projected_px, "
    "filled_unknown_px, rejected_fov_px, rejected_occlusion_px, rejected_neighbourhood_px, "
    "rejected_uncertain_px, tolerance_px, tolerance_m, fallback";
constexpr int kModelColumnCount = 38;

// NaN is stored as NULL (SQLite cannot keep it; PostgreSQL could, but both engines store alike).
void BindReal(Statement& s, int index, double v) {
  if (std::isnan(v)) s.BindNull(index);
  else s.Bind(index, v);
}

double RealOrNaN(const Statement& s, int column) {
  return s.IsNull(column) ? std::numeric_limits<double>::quiet_NaN() : s.Double(column);
}

MergedModelRecord ReadModel(const Statement& s, int f) {
  MergedModelRecord m;
  m.scene_id = s.Int(f);
  m.icp_converged = s.Int(f + 1) != 0;
  m.icp_applied = s.Int(f + 2) != 0;
  m.fitness_m2 = RealOrNaN(s, f + 3);
  m.fitness_before_m2 = RealOrNaN(s, f + 4);
  for (int k = 0; k < 3; ++k) m.correction_translation_m[static_cast<std::size_t>(k)] = RealOrNaN(s, f + 5 + k);
  m.correction_rotation_rad = RealOrNaN(s, f + 8);
  m.source_points = s.Int(f + 9);
  m.target_points = s.Int(f + 10);
  m.icp_verdict = s.Text(f + 11);
  for (int k = 0; k < 6; ++k) m.relative_information[static_cast<std::size_t>(k)] = RealOrNaN(s, f + 12 + k);
  m.unobservable_directions = s.Int(f + 18);
  m.mahalanobis2 = RealOrNaN(s, f + 19);
  for (int k = 0; k < 6; ++k) m.remaining_sigma[static_cast<std::size_t>(k)] = RealOrNaN(s, f + 20 + k);
  std::int64_t* const pixels[] = {&m.rasterised_px, &m.supported_px, &m.replaced_farther_px, &m.rear_projected_px,
                                  &m.filled_unknown_px, &m.rejected_fov_px, &m.rejected_occlusion_px,
                                  &m.rejected_neighbourhood_px, &m.rejected_uncertain_px};
  for (int k = 0; k < 9; ++k) *pixels[k] = s.Int(f + 26 + k);
  m.tolerance_px = RealOrNaN(s, f + 35);
  m.tolerance_m = RealOrNaN(s, f + 36);
  m.fallback = s.Text(f + 37);
  return m;
}

void BindModel(Statement& s, int f, const MergedModelRecord& m) {
  s.Bind(f, m.scene_id).Bind(f + 1, std::int64_t{m.icp_converged}).Bind(f + 2, std::int64_t{m.icp_applied});
  BindReal(s, f + 3, m.fitness_m2);
  BindReal(s, f + 4, m.fitness_before_m2);
  for (int k = 0; k < 3; ++k) BindReal(s, f + 5 + k, m.correction_translation_m[static_cast<std::size_t>(k)]);
  BindReal(s, f + 8, m.correction_rotation_rad);
  s.Bind(f + 9, m.source_points).Bind(f + 10, m.target_points).Bind(f + 11, m.icp_verdict);
  for (int k = 0; k < 6; ++k) BindReal(s, f + 12 + k, m.relative_information[static_cast<std::size_t>(k)]);
  s.Bind(f + 18, m.unobservable_directions);
  BindReal(s, f + 19, m.mahalanobis2);
  for (int k = 0; k < 6; ++k) BindReal(s, f + 20 + k, m.remaining_sigma[static_cast<std::size_t>(k)]);
  const std::int64_t pixels[] = {m.rasterised_px, m.supported_px, m.replaced_farther_px, m.rear_projected_px,
                                 m.filled_unknown_px, m.rejected_fov_px, m.rejected_occlusion_px,
                                 m.rejected_neighbourhood_px, m.rejected_uncertain_px};
  for (int k = 0; k < 9; ++k) s.Bind(f + 26 + k, pixels[k]);
  BindReal(s, f + 35, m.tolerance_px);
  BindReal(s, f + 36, m.tolerance_m);
  s.Bind(f + 37, m.fallback);
}

}  // namespace

std::int64_t Read(const Statement& s, int f, MergeReportRecord& r) {
  r.requested = s.Int(f) != 0;
  r.strategy = s.Text(f + 1);
  if (!s.IsNull(f + 2)) r.pending = s.Int(f + 2) != 0;
  r.performed = s.Int(f + 3) != 0;
  r.icp_ms = RealOrNaN(s, f + 4);
  r.rasterise_ms = RealOrNaN(s, f + 5);
  r.merge_ms = RealOrNaN(s, f + 6);
  if (!s.IsNull(f + 13)) {
    std::array<double, 7> pose{};
    for (int k = 0; k < 7; ++k) pose[static_cast<std::size_t>(k)] = RealOrNaN(s, f + 7 + k);
    r.pose_corrected = pose;
  }
  r.corrected_by_scene = OptionalInt(s, f + 14);
  return s.Int(f + 15);
}

void Bind(Statement& s, int f, const MergeReportRecord& r) {
  s.Bind(f, std::int64_t{r.requested}).Bind(f + 1, r.strategy);
  if (r.pending) s.Bind(f + 2, std::int64_t{*r.pending});
  else s.BindNull(f + 2);
  s.Bind(f + 3, std::int64_t{r.performed});
  BindReal(s, f + 4, r.icp_ms);
  BindReal(s, f + 5, r.rasterise_ms);
  BindReal(s, f + 6, r.merge_ms);
  for (int k = 0; k < 7; ++k) {
    if (r.pose_corrected) BindReal(s, f + 7 + k, (*r.pose_corrected)[static_cast<std::size_t>(k)]);
    else s.BindNull(f + 7 + k);
  }
  BindOptional(s, f + 14, r.corrected_by_scene);
  s.Bind(f + 15, static_cast<std::int64_t>(r.candidates.size() + r.models_used.size() + r.superseded.size()));
}

void ReadLists(Connection& c, std::int64_t scene_id, MergeReportRecord& r) {
  {
    Statement s(c, "SELECT candidate_scene, overlap FROM scene_merge_candidates WHERE scene_id = ? ORDER BY position");
    s.Bind(1, scene_id);
    while (s.Step()) r.candidates.push_back({s.Int(0), RealOrNaN(s, 1)});
  }
  {
    Statement s(c, std::string("SELECT ") + kModelColumns + " FROM scene_merge_models WHERE scene_id = ? ORDER BY position");
    s.Bind(1, scene_id);
    while (s.Step()) r.models_used.push_back(ReadModel(s, 0));
  }
  Statement s(c, "SELECT superseded_scene FROM scene_merge_superseded WHERE scene_id = ? ORDER BY position");
  s.Bind(1, scene_id);
  while (s.Step()) r.superseded.push_back(s.Int(0));
}

void ReplaceLists(Connection& c, std::int64_t scene_id, const MergeReportRecord& r) {
  for (const char* table : {"scene_merge_candidates", "scene_merge_models", "scene_merge_superseded"}) {
    Statement(c, std::string("DELETE FROM ") + table + " WHERE scene_id = ?").Bind(1, scene_id).Run();
  }
  for (std::size_t i = 0; i < r.candidates.size(); ++i) {
    Statement s(c, "INSERT INTO scene_merge_candidates (scene_id, position, candidate_scene, overlap) VALUES (?, ?, ?, ?)");
    s.Bind(1, scene_id).Bind(2, static_cast<std::int64_t>(i)).Bind(3, r.candidates[i].scene_id);
    BindReal(s, 4, r.candidates[i].overlap);
    s.Run();
  }
  std::string placeholders = "?, ?";
  for (int k = 0; k < kModelColumnCount; ++k) placeholders += ", ?";
  for (std::size_t i = 0; i < r.models_used.size(); ++i) {
    Statement s(c, std::string("INSERT INTO scene_merge_models (scene_id, position, ") + kModelColumns + ") VALUES (" +
                       placeholders + ")");
    s.Bind(1, scene_id).Bind(2, static_cast<std::int64_t>(i));
    BindModel(s, 3, r.models_used[i]);
    s.Run();
  }
  for (std::size_t i = 0; i < r.superseded.size(); ++i) {
    Statement(c, "INSERT INTO scene_merge_superseded (scene_id, position, superseded_scene) VALUES (?, ?, ?)")
        .Bind(1, scene_id).Bind(2, static_cast<std::int64_t>(i)).Bind(3, r.superseded[i]).Run();
  }
}

}  // namespace anchordb::storage::merge_report
