-- 0009: the durable queue of keyframe change analyses (thesis 3.3.4; SPEC §8). The frame, keyframe or close
-- transaction that stores a keyframe inserts its row here; the analysis worker (services/events/analysis_queue.h)
-- takes the rows of one map oldest keyframe first, writes the analysis' events and deletes the row in one
-- transaction. Rows left by a stop or a crash resume at the next start. A keyframe deleted meanwhile (forgetting, its
-- scene or map deleted) takes its row with it.
CREATE TABLE keyframe_analysis_queue (
  keyframe_id     INTEGER PRIMARY KEY REFERENCES keyframes(id) ON DELETE CASCADE,
  map_id          TEXT NOT NULL REFERENCES maps(id) ON DELETE CASCADE,
  scene_id        INTEGER NOT NULL REFERENCES scene_models(id) ON DELETE CASCADE,
  enqueued_ns     INTEGER NOT NULL,
  attempts        INTEGER NOT NULL DEFAULT 0,   -- failed attempts so far
  next_attempt_ns INTEGER NOT NULL DEFAULT 0,   -- not before (backoff after a failure)
  last_error      TEXT,                         -- the last failure's message; NULL before any
  failed          INTEGER NOT NULL DEFAULT 0    -- 1: given up after a non-transient error (kept for the operator)
);
CREATE INDEX keyframe_analysis_queue_by_map ON keyframe_analysis_queue (map_id, keyframe_id);
