-- 0009: the durable queue of keyframe change analyses (thesis 3.3.4; SPEC §8). PostgreSQL form of sqlite/0009.
CREATE TABLE keyframe_analysis_queue (
  keyframe_id     BIGINT PRIMARY KEY REFERENCES keyframes(id) ON DELETE CASCADE,
  map_id          TEXT NOT NULL REFERENCES maps(id) ON DELETE CASCADE,
  scene_id        BIGINT NOT NULL REFERENCES scene_models(id) ON DELETE CASCADE,
  enqueued_ns     BIGINT NOT NULL,
  attempts        BIGINT NOT NULL DEFAULT 0,
  next_attempt_ns BIGINT NOT NULL DEFAULT 0,
  last_error      TEXT,
  failed          BIGINT NOT NULL DEFAULT 0
);
CREATE INDEX keyframe_analysis_queue_by_map ON keyframe_analysis_queue (map_id, keyframe_id);
