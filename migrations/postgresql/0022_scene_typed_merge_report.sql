-- 0022: a scene model's merge report becomes typed columns of its row and three child tables instead of one JSON
-- document. PostgreSQL form of sqlite/0022 (filled with jsonb operators, the same defaults; positions 0-based).
ALTER TABLE scene_models
  ADD COLUMN merge_requested INTEGER NOT NULL DEFAULT 1,
  ADD COLUMN merge_strategy TEXT NOT NULL DEFAULT 'algorithm2'
    CHECK (merge_strategy IN ('algorithm2', 'naive', 'naive_without_icp')),
  ADD COLUMN merge_pending INTEGER,
  ADD COLUMN merge_performed INTEGER NOT NULL DEFAULT 0,
  ADD COLUMN merge_icp_ms DOUBLE PRECISION,
  ADD COLUMN merge_rasterise_ms DOUBLE PRECISION,
  ADD COLUMN merge_merge_ms DOUBLE PRECISION,
  ADD COLUMN corrected_x_m DOUBLE PRECISION,
  ADD COLUMN corrected_y_m DOUBLE PRECISION,
  ADD COLUMN corrected_z_m DOUBLE PRECISION,
  ADD COLUMN corrected_qx DOUBLE PRECISION,
  ADD COLUMN corrected_qy DOUBLE PRECISION,
  ADD COLUMN corrected_qz DOUBLE PRECISION,
  ADD COLUMN corrected_qw DOUBLE PRECISION,
  ADD COLUMN corrected_by_scene BIGINT,
  ADD COLUMN merge_list_rows INTEGER NOT NULL DEFAULT 0;

-- The candidates chosen when the model was opened, in order.
CREATE TABLE scene_merge_candidates (
  scene_id          BIGINT NOT NULL REFERENCES scene_models(id) ON DELETE CASCADE,
  position          INTEGER NOT NULL,
  candidate_scene   BIGINT NOT NULL,
  overlap           DOUBLE PRECISION,
  PRIMARY KEY (scene_id, position)
);
-- What each earlier model contributed to the merge, in order: its registration (ICP) and the pixel counts of the
-- merge premises.
CREATE TABLE scene_merge_models (
  scene_id                 BIGINT NOT NULL REFERENCES scene_models(id) ON DELETE CASCADE,
  position                 INTEGER NOT NULL,
  merged_scene             BIGINT NOT NULL,
  icp_converged            INTEGER NOT NULL,
  icp_applied              INTEGER NOT NULL,
  fitness_m2               DOUBLE PRECISION,
  fitness_before_m2        DOUBLE PRECISION,
  correction_x_m           DOUBLE PRECISION,
  correction_y_m           DOUBLE PRECISION,
  correction_z_m           DOUBLE PRECISION,
  correction_rotation_rad  DOUBLE PRECISION,
  source_points            BIGINT NOT NULL,
  target_points            BIGINT NOT NULL,
  icp_verdict              TEXT NOT NULL,
  information_tx           DOUBLE PRECISION,
  information_ty           DOUBLE PRECISION,
  information_tz           DOUBLE PRECISION,
  information_rx           DOUBLE PRECISION,
  information_ry           DOUBLE PRECISION,
  information_rz           DOUBLE PRECISION,
  unobservable_directions  INTEGER NOT NULL,
  mahalanobis2             DOUBLE PRECISION,
  sigma_tx_m               DOUBLE PRECISION,
  sigma_ty_m               DOUBLE PRECISION,
  sigma_tz_m               DOUBLE PRECISION,
  sigma_rx_rad             DOUBLE PRECISION,
  sigma_ry_rad             DOUBLE PRECISION,
  sigma_rz_rad             DOUBLE PRECISION,
  rasterised_px            BIGINT NOT NULL,
  supported_px             BIGINT NOT NULL,
  replaced_farther_px      BIGINT NOT NULL,
  rear_projected_px        BIGINT NOT NULL,
  filled_unknown_px        BIGINT NOT NULL,
  rejected_fov_px          BIGINT NOT NULL,
  rejected_occlusion_px    BIGINT NOT NULL,
  rejected_neighbourhood_px BIGINT NOT NULL,
  rejected_uncertain_px    BIGINT NOT NULL,
  tolerance_px             DOUBLE PRECISION,
  tolerance_m              DOUBLE PRECISION,
  fallback                 TEXT NOT NULL,
  PRIMARY KEY (scene_id, position)
);
-- The earlier models this one superseded, in order.
CREATE TABLE scene_merge_superseded (
  scene_id          BIGINT NOT NULL REFERENCES scene_models(id) ON DELETE CASCADE,
  position          INTEGER NOT NULL,
  superseded_scene  BIGINT NOT NULL,
  PRIMARY KEY (scene_id, position)
);

UPDATE scene_models SET
  merge_requested = CASE WHEN (merge_report::jsonb ->> 'requested')::boolean IS FALSE THEN 0 ELSE 1 END,
  merge_strategy = CASE merge_report::jsonb ->> 'strategy' WHEN 'naive' THEN 'naive'
                   WHEN 'naive_without_icp' THEN 'naive_without_icp' ELSE 'algorithm2' END,
  merge_pending = CASE (merge_report::jsonb ->> 'pending')::boolean WHEN TRUE THEN 1 WHEN FALSE THEN 0 END,
  merge_performed = CASE WHEN (merge_report::jsonb ->> 'performed')::boolean THEN 1 ELSE 0 END,
  merge_icp_ms = CASE WHEN merge_report::jsonb -> 'timing_ms' IS NULL THEN 0
    ELSE (merge_report::jsonb #>> '{timing_ms,icp}')::double precision END,
  merge_rasterise_ms = CASE WHEN merge_report::jsonb -> 'timing_ms' IS NULL THEN 0
    ELSE (merge_report::jsonb #>> '{timing_ms,rasterise}')::double precision END,
  merge_merge_ms = CASE WHEN merge_report::jsonb -> 'timing_ms' IS NULL THEN 0
    ELSE (merge_report::jsonb #>> '{timing_ms,merge}')::double precision END,
  corrected_by_scene = (merge_report::jsonb ->> 'pose_corrected_by_scene')::bigint;
UPDATE scene_models SET
  corrected_x_m = (merge_report::jsonb #>> '{pose_corrected,position,0}')::double precision,
  corrected_y_m = (merge_report::jsonb #>> '{pose_corrected,position,1}')::double precision,
  corrected_z_m = (merge_report::jsonb #>> '{pose_corrected,position,2}')::double precision,
  corrected_qx = (merge_report::jsonb #>> '{pose_corrected,orientation,0}')::double precision,
  corrected_qy = (merge_report::jsonb #>> '{pose_corrected,orientation,1}')::double precision,
  corrected_qz = (merge_report::jsonb #>> '{pose_corrected,orientation,2}')::double precision,
  corrected_qw = (merge_report::jsonb #>> '{pose_corrected,orientation,3}')::double precision
WHERE jsonb_typeof(merge_report::jsonb -> 'pose_corrected') = 'object';
INSERT INTO scene_merge_candidates (scene_id, position, candidate_scene, overlap)
  SELECT m.id, c.n - 1, (c.v ->> 'scene')::bigint, (c.v ->> 'overlap')::double precision
  FROM scene_models m, jsonb_array_elements(CASE WHEN jsonb_typeof(m.merge_report::jsonb -> 'candidates') = 'array'
                                             THEN m.merge_report::jsonb -> 'candidates' END) WITH ORDINALITY AS c(v, n);
INSERT INTO scene_merge_superseded (scene_id, position, superseded_scene)
  SELECT m.id, s.n - 1, (s.v #>> '{}')::bigint
  FROM scene_models m, jsonb_array_elements(CASE WHEN jsonb_typeof(m.merge_report::jsonb -> 'superseded') = 'array'
                                             THEN m.merge_report::jsonb -> 'superseded' END) WITH ORDINALITY AS s(v, n);
INSERT INTO scene_merge_models (scene_id, position, merged_scene, icp_converged, icp_applied, fitness_m2,
  fitness_before_m2, correction_x_m,
  correction_y_m, correction_z_m, correction_rotation_rad, source_points, target_points, icp_verdict,
  information_tx, information_ty, information_tz, information_rx, information_ry, information_rz,
  unobservable_directions, mahalanobis2, sigma_tx_m, sigma_ty_m, sigma_tz_m, sigma_rx_rad, sigma_ry_rad,
  sigma_rz_rad, rasterised_px, supported_px, replaced_farther_px, rear_projected_px, filled_unknown_px,
  rejected_fov_px, rejected_occlusion_px, rejected_neighbourhood_px, rejected_uncertain_px, tolerance_px,
  tolerance_m, fallback)
  SELECT m.id,
    u.n - 1,
    (u.v #>> '{scene}')::bigint,
    CASE WHEN (u.v #>> '{icp,converged}')::boolean THEN 1 ELSE 0 END,
    CASE WHEN (u.v #>> '{icp,applied}')::boolean THEN 1 ELSE 0 END,
    (u.v #>> '{icp,fitness_m2}')::double precision,
    (u.v #>> '{icp,fitness_before_m2}')::double precision,
    CASE WHEN u.v #> '{icp,correction,translation_m}' IS NULL THEN 0
      ELSE (u.v #>> '{icp,correction,translation_m,0}')::double precision END,
    CASE WHEN u.v #> '{icp,correction,translation_m}' IS NULL THEN 0
      ELSE (u.v #>> '{icp,correction,translation_m,1}')::double precision END,
    CASE WHEN u.v #> '{icp,correction,translation_m}' IS NULL THEN 0
      ELSE (u.v #>> '{icp,correction,translation_m,2}')::double precision END,
    (u.v #>> '{icp,correction,rotation_rad}')::double precision,
    COALESCE((u.v #>> '{icp,source_points}')::bigint, 0),
    COALESCE((u.v #>> '{icp,target_points}')::bigint, 0),
    COALESCE(u.v #>> '{icp,verdict}', ''),
    COALESCE((u.v #>> '{icp,relative_information,0}')::double precision, 0),
    COALESCE((u.v #>> '{icp,relative_information,1}')::double precision, 0),
    COALESCE((u.v #>> '{icp,relative_information,2}')::double precision, 0),
    COALESCE((u.v #>> '{icp,relative_information,3}')::double precision, 0),
    COALESCE((u.v #>> '{icp,relative_information,4}')::double precision, 0),
    COALESCE((u.v #>> '{icp,relative_information,5}')::double precision, 0),
    COALESCE((u.v #>> '{icp,unobservable_directions}')::integer, 0),
    (u.v #>> '{icp,mahalanobis2}')::double precision,
    COALESCE((u.v #>> '{icp,remaining_sigma,0}')::double precision, 0),
    COALESCE((u.v #>> '{icp,remaining_sigma,1}')::double precision, 0),
    COALESCE((u.v #>> '{icp,remaining_sigma,2}')::double precision, 0),
    COALESCE((u.v #>> '{icp,remaining_sigma,3}')::double precision, 0),
    COALESCE((u.v #>> '{icp,remaining_sigma,4}')::double precision, 0),
    COALESCE((u.v #>> '{icp,remaining_sigma,5}')::double precision, 0),
    COALESCE((u.v #>> '{pixels,rasterised}')::bigint, 0),
    COALESCE((u.v #>> '{pixels,supported}')::bigint, 0),
    COALESCE((u.v #>> '{pixels,replaced_farther}')::bigint, 0),
    COALESCE((u.v #>> '{pixels,rear_projected}')::bigint, 0),
    COALESCE((u.v #>> '{pixels,filled_unknown}')::bigint, 0),
    COALESCE((u.v #>> '{pixels,rejected_fov}')::bigint, 0),
    COALESCE((u.v #>> '{pixels,rejected_occlusion}')::bigint, 0),
    COALESCE((u.v #>> '{pixels,rejected_neighbourhood}')::bigint, 0),
    COALESCE((u.v #>> '{pixels,rejected_uncertain}')::bigint, 0),
    COALESCE((u.v #>> '{premises,tolerance_px}')::double precision, 0),
    COALESCE((u.v #>> '{premises,tolerance_m}')::double precision, 0),
    COALESCE(u.v #>> '{premises,fallback}', '')
  FROM scene_models m, jsonb_array_elements(CASE WHEN jsonb_typeof(m.merge_report::jsonb -> 'models_used') = 'array'
                                             THEN m.merge_report::jsonb -> 'models_used' END) WITH ORDINALITY AS u(v, n);
UPDATE scene_models SET merge_list_rows =
  (SELECT count(*) FROM scene_merge_candidates c WHERE c.scene_id = scene_models.id) +
  (SELECT count(*) FROM scene_merge_models u WHERE u.scene_id = scene_models.id) +
  (SELECT count(*) FROM scene_merge_superseded s WHERE s.scene_id = scene_models.id);
ALTER TABLE scene_models DROP COLUMN merge_report;
