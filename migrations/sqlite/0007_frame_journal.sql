-- 0007: the frame journal (SPEC §8: every acknowledged frame is durable, not only every checkpoint).
-- Each frame an observing scene model applied is committed here before it is answered; a model is rebuilt from its
-- last checkpoint (the state blobs of scene_models, `frames` frames) plus its rows with frame > frames. A checkpoint
-- deletes, in its own transaction, the rows it covers except the row of its last frame, which stays: it holds the
-- latest depth (for manual and end keyframes) and the detector state after it. Closing a model deletes them all.
CREATE TABLE scene_frame_journal (
  id              INTEGER PRIMARY KEY,
  scene_id        INTEGER NOT NULL REFERENCES scene_models(id) ON DELETE CASCADE,
  frame           INTEGER NOT NULL,   -- the model's frame count with this frame applied (the first frame is 1)
  stamp_ns        INTEGER NOT NULL,
  depth_codec     TEXT NOT NULL CHECK (depth_codec IN ('png', 'raw_zstd')),
  depth           BLOB NOT NULL,      -- png: the 16-bit PNG as received; raw_zstd: u16 {h, w} blob (storage/blob_codec.h)
  depth_scale     REAL NOT NULL,      -- sensor units per metre the frame was applied with
  dynamic         BLOB,               -- the dynamic-mask PNG as received; NULL when the frame had none
  model_after     TEXT NOT NULL,      -- JSON: the frame's pixel counts and the settle detector after it (and after
                                      -- any keyframe stored before the next frame)
  UNIQUE (scene_id, frame)
);
