-- 0017: a scene model's camera, pose and parameters become typed columns instead of JSON documents (issue 30: stored
-- documents are typed records; JSON exists only in the API). Filled from the documents of earlier schemas with
-- SQLite's JSON functions, then the document columns are dropped. Values a document lacked take the defaults the
-- server applied when reading it (beta 0.03, dynamic_mode 'exclude', depth_scale 1000, an identity orientation).
ALTER TABLE scene_models ADD COLUMN width_px INTEGER NOT NULL DEFAULT 0;
ALTER TABLE scene_models ADD COLUMN height_px INTEGER NOT NULL DEFAULT 0;
ALTER TABLE scene_models ADD COLUMN fx_px REAL NOT NULL DEFAULT 0;
ALTER TABLE scene_models ADD COLUMN fy_px REAL NOT NULL DEFAULT 0;
ALTER TABLE scene_models ADD COLUMN cx_px REAL NOT NULL DEFAULT 0;
ALTER TABLE scene_models ADD COLUMN cy_px REAL NOT NULL DEFAULT 0;
-- the orientation of the camera's optical frame in the map frame (x_m, y_m, z_m hold its position)
ALTER TABLE scene_models ADD COLUMN qx REAL NOT NULL DEFAULT 0;
ALTER TABLE scene_models ADD COLUMN qy REAL NOT NULL DEFAULT 0;
ALTER TABLE scene_models ADD COLUMN qz REAL NOT NULL DEFAULT 0;
ALTER TABLE scene_models ADD COLUMN qw REAL NOT NULL DEFAULT 1;
ALTER TABLE scene_models ADD COLUMN beta REAL NOT NULL DEFAULT 0.03;
ALTER TABLE scene_models ADD COLUMN dynamic_mode TEXT NOT NULL DEFAULT 'exclude' CHECK (dynamic_mode IN ('exclude', 'subtract'));
ALTER TABLE scene_models ADD COLUMN depth_scale REAL NOT NULL DEFAULT 1000;
UPDATE scene_models SET
  width_px = COALESCE(json_extract(intrinsics, '$.width'), 0),
  height_px = COALESCE(json_extract(intrinsics, '$.height'), 0),
  fx_px = COALESCE(json_extract(intrinsics, '$.fx'), 0),
  fy_px = COALESCE(json_extract(intrinsics, '$.fy'), 0),
  cx_px = COALESCE(json_extract(intrinsics, '$.cx'), 0),
  cy_px = COALESCE(json_extract(intrinsics, '$.cy'), 0),
  qx = COALESCE(json_extract(pose, '$.orientation[0]'), 0),
  qy = COALESCE(json_extract(pose, '$.orientation[1]'), 0),
  qz = COALESCE(json_extract(pose, '$.orientation[2]'), 0),
  qw = COALESCE(json_extract(pose, '$.orientation[3]'), 1),
  beta = COALESCE(json_extract(params, '$.beta'), 0.03),
  dynamic_mode = CASE json_extract(params, '$.dynamic_mode') WHEN 'subtract' THEN 'subtract' ELSE 'exclude' END,
  depth_scale = COALESCE(json_extract(params, '$.depth_scale'), 1000);
ALTER TABLE scene_models DROP COLUMN intrinsics;
ALTER TABLE scene_models DROP COLUMN pose;
ALTER TABLE scene_models DROP COLUMN params;
