-- 0017: a scene model's camera, pose and parameters become typed columns instead of JSON documents. PostgreSQL form
-- of sqlite/0017 (filled with jsonb operators; the same defaults for what a document lacked).
ALTER TABLE scene_models
  ADD COLUMN width_px INTEGER NOT NULL DEFAULT 0,
  ADD COLUMN height_px INTEGER NOT NULL DEFAULT 0,
  ADD COLUMN fx_px DOUBLE PRECISION NOT NULL DEFAULT 0,
  ADD COLUMN fy_px DOUBLE PRECISION NOT NULL DEFAULT 0,
  ADD COLUMN cx_px DOUBLE PRECISION NOT NULL DEFAULT 0,
  ADD COLUMN cy_px DOUBLE PRECISION NOT NULL DEFAULT 0,
  ADD COLUMN qx DOUBLE PRECISION NOT NULL DEFAULT 0,
  ADD COLUMN qy DOUBLE PRECISION NOT NULL DEFAULT 0,
  ADD COLUMN qz DOUBLE PRECISION NOT NULL DEFAULT 0,
  ADD COLUMN qw DOUBLE PRECISION NOT NULL DEFAULT 1,
  ADD COLUMN beta DOUBLE PRECISION NOT NULL DEFAULT 0.03,
  ADD COLUMN dynamic_mode TEXT NOT NULL DEFAULT 'exclude' CHECK (dynamic_mode IN ('exclude', 'subtract')),
  ADD COLUMN depth_scale DOUBLE PRECISION NOT NULL DEFAULT 1000;
UPDATE scene_models SET
  width_px = COALESCE((intrinsics::jsonb ->> 'width')::integer, 0),
  height_px = COALESCE((intrinsics::jsonb ->> 'height')::integer, 0),
  fx_px = COALESCE((intrinsics::jsonb ->> 'fx')::double precision, 0),
  fy_px = COALESCE((intrinsics::jsonb ->> 'fy')::double precision, 0),
  cx_px = COALESCE((intrinsics::jsonb ->> 'cx')::double precision, 0),
  cy_px = COALESCE((intrinsics::jsonb ->> 'cy')::double precision, 0),
  qx = COALESCE((pose::jsonb #>> '{orientation,0}')::double precision, 0),
  qy = COALESCE((pose::jsonb #>> '{orientation,1}')::double precision, 0),
  qz = COALESCE((pose::jsonb #>> '{orientation,2}')::double precision, 0),
  qw = COALESCE((pose::jsonb #>> '{orientation,3}')::double precision, 1),
  beta = COALESCE((params::jsonb ->> 'beta')::double precision, 0.03),
  dynamic_mode = CASE params::jsonb ->> 'dynamic_mode' WHEN 'subtract' THEN 'subtract' ELSE 'exclude' END,
  depth_scale = COALESCE((params::jsonb ->> 'depth_scale')::double precision, 1000);
ALTER TABLE scene_models DROP COLUMN intrinsics, DROP COLUMN pose, DROP COLUMN params;
