#pragma once
// The merge report of a scene model as stored (migration 0022): scalar columns of its scene_models row and three child
// tables, scene_merge_candidates, scene_merge_models and scene_merge_superseded. Plain types only (storage depends on
// schema/ alone); services/scene maps them to its MergeReport. A number that was not a number (NaN) is stored as
// NULL and reads back as NaN.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace anchordb::storage {

struct MergeCandidateRecord {
  std::int64_t scene_id = 0;
  double overlap = 0.0;
};

// What one earlier model contributed (engine::MergeModelReport and its registration, engine::IcpResult).
struct MergedModelRecord {
  std::int64_t scene_id = 0;
  bool icp_converged = false;
  bool icp_applied = false;
  double fitness_m2 = 0.0;
  double fitness_before_m2 = 0.0;
  std::array<double, 3> correction_translation_m{};
  double correction_rotation_rad = 0.0;
  std::int64_t source_points = 0;
  std::int64_t target_points = 0;
  std::string icp_verdict;
  std::array<double, 6> relative_information{};  // [tx ty tz rx ry rz]
  std::int64_t unobservable_directions = 0;
  double mahalanobis2 = 0.0;
  std::array<double, 6> remaining_sigma{};  // [m, m, m, rad, rad, rad]
  std::int64_t rasterised_px = 0;
  std::int64_t supported_px = 0;
  std::int64_t replaced_farther_px = 0;
  std::int64_t rear_projected_px = 0;
  std::int64_t filled_unknown_px = 0;
  std::int64_t rejected_fov_px = 0;
  std::int64_t rejected_occlusion_px = 0;
  std::int64_t rejected_neighbourhood_px = 0;
  std::int64_t rejected_uncertain_px = 0;
  double tolerance_px = 0.0;
  double tolerance_m = 0.0;
  std::string fallback;
};

struct MergeReportRecord {
  bool requested = true;
  std::string strategy = "algorithm2";
  std::vector<MergeCandidateRecord> candidates;
  std::optional<bool> pending;
  bool performed = false;
  std::vector<MergedModelRecord> models_used;
  double icp_ms = 0.0;
  double rasterise_ms = 0.0;
  double merge_ms = 0.0;
  std::vector<std::int64_t> superseded;
  // The corrected camera pose: x_m, y_m, z_m, qx, qy, qz, qw (map frame).
  std::optional<std::array<double, 7>> pose_corrected;
  std::optional<std::int64_t> corrected_by_scene;
};

}  // namespace anchordb::storage
