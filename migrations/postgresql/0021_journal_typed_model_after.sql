-- 0021: a journalled frame's model_after becomes typed columns instead of a JSON document. PostgreSQL form of
-- sqlite/0021 (filled with jsonb operators).
ALTER TABLE scene_frame_journal
  ADD COLUMN supported_px BIGINT NOT NULL DEFAULT 0,
  ADD COLUMN reset_px BIGINT NOT NULL DEFAULT 0,
  ADD COLUMN movable_px BIGINT NOT NULL DEFAULT 0,
  ADD COLUMN dynamic_px BIGINT NOT NULL DEFAULT 0,
  ADD COLUMN no_depth_px BIGINT NOT NULL DEFAULT 0,
  ADD COLUMN settle_movable_at_keyframe_px BIGINT NOT NULL DEFAULT 0,
  ADD COLUMN settle_reset_since_keyframe_px BIGINT NOT NULL DEFAULT 0,
  ADD COLUMN settle_previous_movable_px BIGINT NOT NULL DEFAULT -1,
  ADD COLUMN settle_stable_frames BIGINT NOT NULL DEFAULT 0;
UPDATE scene_frame_journal SET
  supported_px = COALESCE((model_after::jsonb #>> '{counts,supported}')::bigint, 0),
  reset_px = COALESCE((model_after::jsonb #>> '{counts,reset}')::bigint, 0),
  movable_px = COALESCE((model_after::jsonb #>> '{counts,movable}')::bigint, 0),
  dynamic_px = COALESCE((model_after::jsonb #>> '{counts,dynamic}')::bigint, 0),
  no_depth_px = COALESCE((model_after::jsonb #>> '{counts,no_depth}')::bigint, 0),
  settle_movable_at_keyframe_px = COALESCE((model_after::jsonb #>> '{settle,movable_at_keyframe}')::bigint, 0),
  settle_reset_since_keyframe_px = COALESCE((model_after::jsonb #>> '{settle,reset_since_keyframe}')::bigint, 0),
  settle_previous_movable_px = COALESCE((model_after::jsonb #>> '{settle,previous_movable}')::bigint, -1),
  settle_stable_frames = COALESCE((model_after::jsonb #>> '{settle,stable_frames}')::bigint, 0);
ALTER TABLE scene_frame_journal DROP COLUMN model_after;
