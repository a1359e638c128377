-- 0021: a journalled frame's model_after (the frame's pixel counts and the settle detector after it) becomes typed
-- columns instead of a JSON document (issue 30). Filled from the documents of earlier schemas with SQLite's JSON
-- functions, then the document column is dropped. A value a document lacks reads as the detector's initial
-- state (0; -1 for the previous frame's movable pixels) instead of failing the upgrade.
ALTER TABLE scene_frame_journal ADD COLUMN supported_px INTEGER NOT NULL DEFAULT 0;
ALTER TABLE scene_frame_journal ADD COLUMN reset_px INTEGER NOT NULL DEFAULT 0;
ALTER TABLE scene_frame_journal ADD COLUMN movable_px INTEGER NOT NULL DEFAULT 0;
ALTER TABLE scene_frame_journal ADD COLUMN dynamic_px INTEGER NOT NULL DEFAULT 0;
ALTER TABLE scene_frame_journal ADD COLUMN no_depth_px INTEGER NOT NULL DEFAULT 0;
-- the settle detector (engine/scene/settle.h): movable pixels at the last keyframe, resets since it, movable pixels of
-- the previous frame, frames in a row without change
ALTER TABLE scene_frame_journal ADD COLUMN settle_movable_at_keyframe_px INTEGER NOT NULL DEFAULT 0;
ALTER TABLE scene_frame_journal ADD COLUMN settle_reset_since_keyframe_px INTEGER NOT NULL DEFAULT 0;
ALTER TABLE scene_frame_journal ADD COLUMN settle_previous_movable_px INTEGER NOT NULL DEFAULT -1;
ALTER TABLE scene_frame_journal ADD COLUMN settle_stable_frames INTEGER NOT NULL DEFAULT 0;
UPDATE scene_frame_journal SET
  supported_px = COALESCE(json_extract(model_after, '$.counts.supported'), 0),
  reset_px = COALESCE(json_extract(model_after, '$.counts.reset'), 0),
  movable_px = COALESCE(json_extract(model_after, '$.counts.movable'), 0),
  dynamic_px = COALESCE(json_extract(model_after, '$.counts.dynamic'), 0),
  no_depth_px = COALESCE(json_extract(model_after, '$.counts.no_depth'), 0),
  settle_movable_at_keyframe_px = COALESCE(json_extract(model_after, '$.settle.movable_at_keyframe'), 0),
  settle_reset_since_keyframe_px = COALESCE(json_extract(model_after, '$.settle.reset_since_keyframe'), 0),
  settle_previous_movable_px = COALESCE(json_extract(model_after, '$.settle.previous_movable'), -1),
  settle_stable_frames = COALESCE(json_extract(model_after, '$.settle.stable_frames'), 0);
ALTER TABLE scene_frame_journal DROP COLUMN model_after;
