-- 0022: a scene model's merge report becomes typed columns of its row and three child tables instead of one JSON
-- document (issue 30: stored documents are typed records; JSON exists only in the API). A number the report did not
-- have as a number (NaN was written as null) is NULL. Filled from the documents of earlier schemas with SQLite's
-- JSON functions, taking the defaults the server applied to a report of an older release, then the document column
-- is dropped. merge_list_rows counts the model's rows in the three child tables.
ALTER TABLE scene_models ADD COLUMN merge_requested INTEGER NOT NULL DEFAULT 1;
ALTER TABLE scene_models ADD COLUMN merge_strategy TEXT NOT NULL DEFAULT 'algorithm2'
  CHECK (merge_strategy IN ('algorithm2', 'naive', 'naive_without_icp'));
ALTER TABLE scene_models ADD COLUMN merge_pending INTEGER;
ALTER TABLE scene_models ADD COLUMN merge_performed INTEGER NOT NULL DEFAULT 0;
ALTER TABLE scene_models ADD COLUMN merge_icp_ms REAL;
ALTER TABLE scene_models ADD COLUMN merge_rasterise_ms REAL;
ALTER TABLE scene_models ADD COLUMN merge_merge_ms REAL;
-- the camera pose corrected by the best applied registration (present when corrected_qw is not NULL), and whose
ALTER TABLE scene_models ADD COLUMN corrected_x_m REAL;
ALTER TABLE scene_models ADD COLUMN corrected_y_m REAL;
ALTER TABLE scene_models ADD COLUMN corrected_z_m REAL;
ALTER TABLE scene_models ADD COLUMN corrected_qx REAL;
ALTER TABLE scene_models ADD COLUMN corrected_qy REAL;
ALTER TABLE scene_models ADD COLUMN corrected_qz REAL;
ALTER TABLE scene_models ADD COLUMN corrected_qw REAL;
ALTER TABLE scene_models ADD COLUMN corrected_by_scene INTEGER;
ALTER TABLE scene_models ADD COLUMN merge_list_rows INTEGER NOT NULL DEFAULT 0;

-- The candidates chosen when the model was opened, in order.
CREATE TABLE scene_merge_candidates (
  scene_id          INTEGER NOT NULL REFERENCES scene_models(id) ON DELETE CASCADE,
  position          INTEGER NOT NULL,
  candidate_scene   INTEGER NOT NULL,
  overlap           REAL,
  PRIMARY KEY (scene_id, position)
);
-- What each earlier model contributed to the merge, in order: its registration (ICP) and the pixel counts of the
-- merge premises.
CREATE TABLE scene_merge_models (
  scene_id                 INTEGER NOT NULL REFERENCES scene_models(id) ON DELETE CASCADE,
  position                 INTEGER NOT NULL,
  merged_scene             INTEGER NOT NULL,
  icp_converged            INTEGER NOT NULL,
  icp_applied              INTEGER NOT NULL,
  fitness_m2               REAL,
  fitness_before_m2        REAL,
  correction_x_m           REAL,
  correction_y_m           REAL,
  correction_z_m           REAL,
  correction_rotation_rad  REAL,
  source_points            INTEGER NOT NULL,
  target_points            INTEGER NOT NULL,
  icp_verdict              TEXT NOT NULL,
  information_tx           REAL,
  information_ty           REAL,
  information_tz           REAL,
  information_rx           REAL,
  information_ry           REAL,
  information_rz           REAL,
  unobservable_directions  INTEGER NOT NULL,
  mahalanobis2             REAL,
  sigma_tx_m               REAL,
  sigma_ty_m               REAL,
  sigma_tz_m               REAL,
  sigma_rx_rad             REAL,
  sigma_ry_rad             REAL,
  sigma_rz_rad             REAL,
  rasterised_px            INTEGER NOT NULL,
  supported_px             INTEGER NOT NULL,
  replaced_farther_px      INTEGER NOT NULL,
  rear_projected_px        INTEGER NOT NULL,
  filled_unknown_px        INTEGER NOT NULL,
  rejected_fov_px          INTEGER NOT NULL,
  rejected_occlusion_px    INTEGER NOT NULL,
  rejected_neighbourhood_px INTEGER NOT NULL,
  rejected_uncertain_px    INTEGER NOT NULL,
  tolerance_px             REAL,
  tolerance_m              REAL,
  fallback                 TEXT NOT NULL,
  PRIMARY KEY (scene_id, position)
);
-- The earlier models this one superseded, in order.
CREATE TABLE scene_merge_superseded (
  scene_id          INTEGER NOT NULL REFERENCES scene_models(id) ON DELETE CASCADE,
  position          INTEGER NOT NULL,
  superseded_scene  INTEGER NOT NULL,
  PRIMARY KEY (scene_id, position)
);

UPDATE scene_models SET
  merge_requested = COALESCE(json_extract(merge_report, '$.requested'), 1),
  merge_strategy = CASE json_extract(merge_report, '$.strategy') WHEN 'naive' THEN 'naive'
                   WHEN 'naive_without_icp' THEN 'naive_without_icp' ELSE 'algorithm2' END,
  merge_pending = json_extract(merge_report, '$.pending'),
  merge_performed = COALESCE(json_extract(merge_report, '$.performed'), 0),
  merge_icp_ms = CASE WHEN json_type(merge_report, '$.timing_ms') IS NULL THEN 0
    ELSE json_extract(merge_report, '$.timing_ms.icp') END,
  merge_rasterise_ms = CASE WHEN json_type(merge_report, '$.timing_ms') IS NULL THEN 0
    ELSE json_extract(merge_report, '$.timing_ms.rasterise') END,
  merge_merge_ms = CASE WHEN json_type(merge_report, '$.timing_ms') IS NULL THEN 0
    ELSE json_extract(merge_report, '$.timing_ms.merge') END,
  corrected_by_scene = json_extract(merge_report, '$.pose_corrected_by_scene');
UPDATE scene_models SET
  corrected_x_m = json_extract(merge_report, '$.pose_corrected.position[0]'),
  corrected_y_m = json_extract(merge_report, '$.pose_corrected.position[1]'),
  corrected_z_m = json_extract(merge_report, '$.pose_corrected.position[2]'),
  corrected_qx = json_extract(merge_report, '$.pose_corrected.orientation[0]'),
  corrected_qy = json_extract(merge_report, '$.pose_corrected.orientation[1]'),
  corrected_qz = json_extract(merge_report, '$.pose_corrected.orientation[2]'),
  corrected_qw = json_extract(merge_report, '$.pose_corrected.orientation[3]')
WHERE json_type(merge_report, '$.pose_corrected') = 'object';
INSERT INTO scene_merge_candidates (scene_id, position, candidate_scene, overlap)
  SELECT m.id, c.key, json_extract(c.value, '$.scene'), json_extract(c.value, '$.overlap')
  FROM scene_models m, json_each(m.merge_report, '$.candidates') c
  WHERE json_type(m.merge_report, '$.candidates') = 'array';
INSERT INTO scene_merge_superseded (scene_id, position, superseded_scene)
  SELECT m.id, s.key, s.value FROM scene_models m, json_each(m.merge_report, '$.superseded') s
  WHERE json_type(m.merge_report, '$.superseded') = 'array';
INSERT INTO scene_merge_models (scene_id, position, merged_scene, icp_converged, icp_applied, fitness_m2,
  fitness_before_m2, correction_x_m,
  correction_y_m, correction_z_m, correction_rotation_rad, source_points, target_points, icp_verdict,
  information_tx, information_ty, information_tz, information_rx, information_ry, information_rz,
  unobservable_directions, mahalanobis2, sigma_tx_m, sigma_ty_m, sigma_tz_m, sigma_rx_rad, sigma_ry_rad,
  sigma_rz_rad, rasterised_px, supported_px, replaced_farther_px, rear_projected_px, filled_unknown_px,
  rejected_fov_px, rejected_occlusion_px, rejected_neighbourhood_px, rejected_uncertain_px, tolerance_px,
  tolerance_m, fallback)
  SELECT m.id,
    u.key,
    json_extract(u.value, '$.scene'),
    COALESCE(json_extract(u.value, '$.icp.converged'), 0),
    COALESCE(json_extract(u.value, '$.icp.applied'), 0),
    json_extract(u.value, '$.icp.fitness_m2'),
    json_extract(u.value, '$.icp.fitness_before_m2'),
    CASE WHEN json_type(u.value, '$.icp.correction.translation_m') IS NULL THEN 0
      ELSE json_extract(u.value, '$.icp.correction.translation_m[0]') END,
    CASE WHEN json_type(u.value, '$.icp.correction.translation_m') IS NULL THEN 0
      ELSE json_extract(u.value, '$.icp.correction.translation_m[1]') END,
    CASE WHEN json_type(u.value, '$.icp.correction.translation_m') IS NULL THEN 0
      ELSE json_extract(u.value, '$.icp.correction.translation_m[2]') END,
    json_extract(u.value, '$.icp.correction.rotation_rad'),
    COALESCE(json_extract(u.value, '$.icp.source_points'), 0),
    COALESCE(json_extract(u.value, '$.icp.target_points'), 0),
    COALESCE(json_extract(u.value, '$.icp.verdict'), ''),
    COALESCE(json_extract(u.value, '$.icp.relative_information[0]'), 0),
    COALESCE(json_extract(u.value, '$.icp.relative_information[1]'), 0),
    COALESCE(json_extract(u.value, '$.icp.relative_information[2]'), 0),
    COALESCE(json_extract(u.value, '$.icp.relative_information[3]'), 0),
    COALESCE(json_extract(u.value, '$.icp.relative_information[4]'), 0),
    COALESCE(json_extract(u.value, '$.icp.relative_information[5]'), 0),
    COALESCE(json_extract(u.value, '$.icp.unobservable_directions'), 0),
    json_extract(u.value, '$.icp.mahalanobis2'),
    COALESCE(json_extract(u.value, '$.icp.remaining_sigma[0]'), 0),
    COALESCE(json_extract(u.value, '$.icp.remaining_sigma[1]'), 0),
    COALESCE(json_extract(u.value, '$.icp.remaining_sigma[2]'), 0),
    COALESCE(json_extract(u.value, '$.icp.remaining_sigma[3]'), 0),
    COALESCE(json_extract(u.value, '$.icp.remaining_sigma[4]'), 0),
    COALESCE(json_extract(u.value, '$.icp.remaining_sigma[5]'), 0),
    COALESCE(json_extract(u.value, '$.pixels.rasterised'), 0),
    COALESCE(json_extract(u.value, '$.pixels.supported'), 0),
    COALESCE(json_extract(u.value, '$.pixels.replaced_farther'), 0),
    COALESCE(json_extract(u.value, '$.pixels.rear_projected'), 0),
    COALESCE(json_extract(u.value, '$.pixels.filled_unknown'), 0),
    COALESCE(json_extract(u.value, '$.pixels.rejected_fov'), 0),
    COALESCE(json_extract(u.value, '$.pixels.rejected_occlusion'), 0),
    COALESCE(json_extract(u.value, '$.pixels.rejected_neighbourhood'), 0),
    COALESCE(json_extract(u.value, '$.pixels.rejected_uncertain'), 0),
    COALESCE(json_extract(u.value, '$.premises.tolerance_px'), 0),
    COALESCE(json_extract(u.value, '$.premises.tolerance_m'), 0),
    COALESCE(json_extract(u.value, '$.premises.fallback'), '')
  FROM scene_models m, json_each(m.merge_report, '$.models_used') u
  WHERE json_type(m.merge_report, '$.models_used') = 'array';
UPDATE scene_models SET merge_list_rows =
  (SELECT count(*) FROM scene_merge_candidates c WHERE c.scene_id = scene_models.id) +
  (SELECT count(*) FROM scene_merge_models u WHERE u.scene_id = scene_models.id) +
  (SELECT count(*) FROM scene_merge_superseded s WHERE s.scene_id = scene_models.id);
ALTER TABLE scene_models DROP COLUMN merge_report;
