-- 0004: segments, change events, object instances with their position history, action layers, jobs
-- (thesis 3.3.4, 3.5.2, 1.4; SPEC §3, §4.4, §4.5).
--
-- References that forgetting must respect are foreign keys without a cascade: a keyframe used as event evidence or
-- as a segment's source cannot be deleted while the reference exists (PRAGMA foreign_keys is on), so a forgetting
-- job that got its bookkeeping wrong fails and rolls back instead of leaving a dangling reference.

-- Keyframes gain the kind 'settled' (the movable layer settled after a change: a completed movement), the action
-- layer they close, and a relevance score a high-level component may set (forgetting keeps relevant keyframes).
CREATE TABLE keyframes_v4 (
  id              INTEGER PRIMARY KEY AUTOINCREMENT,
  map_id          TEXT NOT NULL REFERENCES maps(id) ON DELETE CASCADE,
  scene_id        INTEGER NOT NULL REFERENCES scene_models(id) ON DELETE CASCADE,
  kind            TEXT NOT NULL CHECK (kind IN ('begin', 'end', 'manual', 'settled')),
  stamp_ns        INTEGER NOT NULL,
  width           INTEGER NOT NULL,
  height          INTEGER NOT NULL,
  depth           BLOB NOT NULL,      -- u16 {h, w} raw depth [mm], delta-shuffle filtered
  background      BLOB NOT NULL,      -- u16 {h, w} static background at that moment [mm]
  raw_bytes       INTEGER NOT NULL,
  stored_bytes    INTEGER NOT NULL,
  pinned          INTEGER NOT NULL DEFAULT 0,
  action_layer    INTEGER NOT NULL DEFAULT 0,  -- 0 for the begin keyframe; keyframe k closes layer k-1 and opens k
  relevance       REAL NOT NULL DEFAULT 0
);
INSERT INTO keyframes_v4 (id, map_id, scene_id, kind, stamp_ns, width, height, depth, background, raw_bytes,
                          stored_bytes, pinned)
  SELECT id, map_id, scene_id, kind, stamp_ns, width, height, depth, background, raw_bytes, stored_bytes, pinned
  FROM keyframes;
-- The new table inherits the old one's AUTOINCREMENT high-water mark (DROP TABLE deletes it from sqlite_sequence, and
-- the copy alone only records the largest id left): the ids of keyframes deleted before, with their map, are never
-- handed out again. Found by tests/integration/test_old_databases.py on tests/data/schema_0002/0003 files.
INSERT INTO sqlite_sequence (name, seq)
  SELECT 'keyframes_v4', 0 WHERE NOT EXISTS (SELECT 1 FROM sqlite_sequence WHERE name = 'keyframes_v4');
UPDATE sqlite_sequence SET seq = (SELECT MAX(seq) FROM sqlite_sequence WHERE name IN ('keyframes', 'keyframes_v4'))
 WHERE name = 'keyframes_v4';
DROP TABLE keyframes;
ALTER TABLE keyframes_v4 RENAME TO keyframes;
CREATE INDEX keyframes_by_scene ON keyframes (scene_id, stamp_ns);
CREATE INDEX keyframes_by_map_time ON keyframes (map_id, stamp_ns);

-- A superseded model whose state was dropped by forgetting keeps its row (its keyframes may be evidence).
ALTER TABLE scene_models ADD COLUMN forgotten_ns INTEGER;

-- Clusters of movable points in the map frame (Euclidean clustering), from one keyframe comparison.
CREATE TABLE segments (
  id              INTEGER PRIMARY KEY AUTOINCREMENT,
  map_id          TEXT NOT NULL REFERENCES maps(id) ON DELETE CASCADE,
  keyframe_id     INTEGER NOT NULL REFERENCES keyframes(id),  -- the keyframe whose pixels the points came from
  x_m REAL NOT NULL, y_m REAL NOT NULL, z_m REAL NOT NULL,    -- centroid in the map frame
  min_x_m REAL NOT NULL, min_y_m REAL NOT NULL, min_z_m REAL NOT NULL,
  max_x_m REAL NOT NULL, max_y_m REAL NOT NULL, max_z_m REAL NOT NULL,
  points          INTEGER NOT NULL,
  sample          BLOB NOT NULL       -- f32 {n, 3}: up to 256 of its points, for visibility checks later
);
CREATE INDEX segments_by_keyframe ON segments (keyframe_id);

-- Objects (and operator-entered furniture) over time.
CREATE TABLE instances (
  id              INTEGER PRIMARY KEY AUTOINCREMENT,
  map_id          TEXT NOT NULL REFERENCES maps(id) ON DELETE CASCADE,
  kind            TEXT NOT NULL CHECK (kind IN ('object', 'furniture')),
  status          TEXT NOT NULL CHECK (status IN ('present', 'absent', 'deleted')),
  labels          TEXT NOT NULL DEFAULT '{}',   -- JSON {label: evidence weight}; the distribution is its normalisation
  label_locked    INTEGER NOT NULL DEFAULT 0,   -- an operator set the label: automatic processing never changes it
  status_locked   INTEGER NOT NULL DEFAULT 0,   -- an operator deleted it: never revived
  pinned          INTEGER NOT NULL DEFAULT 0,   -- an operator pinned it: forgetting keeps its whole history
  x_m REAL NOT NULL, y_m REAL NOT NULL, z_m REAL NOT NULL,
  extent_x_m REAL NOT NULL, extent_y_m REAL NOT NULL, extent_z_m REAL NOT NULL,
  yaw_rad         REAL NOT NULL DEFAULT 0,
  sample          BLOB,               -- f32 {n, 3}: points of its last segment
  last_seen_ns    INTEGER NOT NULL,
  last_scene_id   INTEGER REFERENCES scene_models(id) ON DELETE SET NULL,
  created_ns      INTEGER NOT NULL,
  updated_ns      INTEGER NOT NULL
);
CREATE INDEX instances_by_map ON instances (map_id, status);

CREATE TABLE events (
  id              INTEGER PRIMARY KEY AUTOINCREMENT,
  map_id          TEXT NOT NULL REFERENCES maps(id) ON DELETE CASCADE,
  type            TEXT NOT NULL CHECK (type IN ('added', 'removed', 'moved', 'labelled')),
  -- observed: between keyframes of one observation; meanwhile: between visits (through the merge); reanalysis: an
  -- old keyframe against a newer background; dialog / operator: labels. type 'moved' is the lost-key inference.
  detection      TEXT NOT NULL CHECK (detection IN ('observed', 'meanwhile', 'reanalysis', 'dialog', 'operator')),
  stamp_ns        INTEGER NOT NULL,
  scene_id        INTEGER REFERENCES scene_models(id) ON DELETE SET NULL,
  action_layer    INTEGER,
  instance_id     INTEGER REFERENCES instances(id),
  segment_id      INTEGER REFERENCES segments(id),
  label           TEXT,
  explanation     TEXT NOT NULL DEFAULT '',
  details         TEXT NOT NULL DEFAULT '{}',   -- JSON: positions, matching figures
  pinned          INTEGER NOT NULL DEFAULT 0,
  created_ns      INTEGER NOT NULL
);
CREATE INDEX events_by_map_time ON events (map_id, stamp_ns);
CREATE INDEX events_by_instance ON events (instance_id, stamp_ns);

-- The keyframes that prove an event ('before' / 'after' the change).
CREATE TABLE event_evidence (
  event_id        INTEGER NOT NULL REFERENCES events(id) ON DELETE CASCADE,
  keyframe_id     INTEGER NOT NULL REFERENCES keyframes(id),
  role            TEXT NOT NULL CHECK (role IN ('before', 'after')),
  PRIMARY KEY (event_id, keyframe_id)
);
CREATE INDEX event_evidence_by_keyframe ON event_evidence (keyframe_id);

-- Every position an instance was known at (present = 0: known to be gone from there).
CREATE TABLE instance_history (
  instance_id     INTEGER NOT NULL REFERENCES instances(id) ON DELETE CASCADE,
  seq             INTEGER NOT NULL,
  stamp_ns        INTEGER NOT NULL,
  present         INTEGER NOT NULL,
  x_m REAL NOT NULL, y_m REAL NOT NULL, z_m REAL NOT NULL,
  event_id        INTEGER REFERENCES events(id) ON DELETE SET NULL,
  PRIMARY KEY (instance_id, seq)
);
CREATE INDEX instance_history_by_time ON instance_history (instance_id, stamp_ns);

-- Long work (forgetting, ...): progress, result and errors; a job found 'running' at start-up was interrupted.
CREATE TABLE jobs (
  id              INTEGER PRIMARY KEY AUTOINCREMENT,
  kind            TEXT NOT NULL,
  map_id          TEXT REFERENCES maps(id) ON DELETE CASCADE,
  status          TEXT NOT NULL CHECK (status IN ('queued', 'running', 'succeeded', 'failed')),
  stage           TEXT NOT NULL DEFAULT '',
  progress        REAL NOT NULL DEFAULT 0,
  request         TEXT NOT NULL DEFAULT '{}',
  result          TEXT,
  error           TEXT,
  created_ns      INTEGER NOT NULL,
  updated_ns      INTEGER NOT NULL
);
