-- 0002: anchored egocentric scene models (thesis 3.2-3.3) and their keyframes (3.3.4).
CREATE TABLE scene_models (
  id              INTEGER PRIMARY KEY AUTOINCREMENT,
  map_id          TEXT NOT NULL REFERENCES maps(id) ON DELETE CASCADE,
  status          TEXT NOT NULL CHECK (status IN ('observing', 'closed', 'superseded')),
  superseded_by   INTEGER REFERENCES scene_models(id) ON DELETE SET NULL,
  intrinsics      TEXT NOT NULL,      -- JSON {width,height,fx,fy,cx,cy}
  pose            TEXT NOT NULL,      -- JSON pose of the camera optical frame in the map frame
  x_m             REAL NOT NULL,      -- camera position, duplicated for spatial queries
  y_m             REAL NOT NULL,
  z_m             REAL NOT NULL,
  params          TEXT NOT NULL,      -- JSON {beta, dynamic_mode, depth_scale}
  merge_report    TEXT NOT NULL DEFAULT '{}',
  started_ns      INTEGER NOT NULL,
  ended_ns        INTEGER,
  last_frame_ns   INTEGER,
  frames          INTEGER NOT NULL DEFAULT 0,  -- frames contained in the persisted state
  state_version   INTEGER NOT NULL DEFAULT 0,  -- increases with every persisted state
  background      BLOB,               -- f32 {h, w} static background [m]
  weight          BLOB,               -- f32 {h, w} reliability
  labels          BLOB                -- u8 {2, h, w}: movable, dynamic
);
CREATE INDEX scene_models_by_map ON scene_models (map_id, status);

CREATE VIRTUAL TABLE scene_models_rtree USING rtree(id, min_x, max_x, min_y, max_y, min_z, max_z);
CREATE TRIGGER scene_models_rtree_insert AFTER INSERT ON scene_models BEGIN
  INSERT INTO scene_models_rtree VALUES (new.id, new.x_m, new.x_m, new.y_m, new.y_m, new.z_m, new.z_m);
END;
CREATE TRIGGER scene_models_rtree_delete AFTER DELETE ON scene_models BEGIN
  DELETE FROM scene_models_rtree WHERE id = old.id;
END;

CREATE TABLE keyframes (
  id              INTEGER PRIMARY KEY AUTOINCREMENT,
  map_id          TEXT NOT NULL REFERENCES maps(id) ON DELETE CASCADE,
  scene_id        INTEGER NOT NULL REFERENCES scene_models(id) ON DELETE CASCADE,
  kind            TEXT NOT NULL CHECK (kind IN ('begin', 'end', 'manual')),
  stamp_ns        INTEGER NOT NULL,
  width           INTEGER NOT NULL,
  height          INTEGER NOT NULL,
  depth           BLOB NOT NULL,      -- u16 {h, w} raw depth [mm], delta-shuffle filtered
  background      BLOB NOT NULL,      -- u16 {h, w} static background at that moment [mm]
  raw_bytes       INTEGER NOT NULL,   -- uncompressed size of both images
  stored_bytes    INTEGER NOT NULL,
  pinned          INTEGER NOT NULL DEFAULT 0
);
CREATE INDEX keyframes_by_scene ON keyframes (scene_id, stamp_ns);
