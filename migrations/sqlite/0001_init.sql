-- 0001: maps, grid layers, agents (with an R*Tree spatial index), API tokens.
CREATE TABLE maps (
  id          TEXT PRIMARY KEY,
  name        TEXT NOT NULL,
  created_ns  INTEGER NOT NULL
);

-- One row per layer. `meta` is JSON (geometry, map_server values, log-odds parameters, fused definition,
-- label table); `data` is a blob in the codec of storage/blob_codec.h (NULL for fused layers, which are derived).
CREATE TABLE layers (
  map_id      TEXT NOT NULL REFERENCES maps(id) ON DELETE CASCADE,
  name        TEXT NOT NULL,
  kind        TEXT NOT NULL CHECK (kind IN ('occupancy', 'probability', 'fused', 'label')),
  meta        TEXT NOT NULL,
  data        BLOB,
  version     INTEGER NOT NULL DEFAULT 1,
  created_ns  INTEGER NOT NULL,
  updated_ns  INTEGER NOT NULL,
  PRIMARY KEY (map_id, name)
);

-- Layers a layer is computed from or anchored to (probability -> its base, fused -> its operands).
-- Deleting a layer something depends on is refused.
CREATE TABLE layer_dependencies (
  map_id      TEXT NOT NULL,
  layer       TEXT NOT NULL,
  depends_on  TEXT NOT NULL,
  PRIMARY KEY (map_id, layer, depends_on),
  FOREIGN KEY (map_id, layer) REFERENCES layers(map_id, name) ON DELETE CASCADE,
  FOREIGN KEY (map_id, depends_on) REFERENCES layers(map_id, name)
);

CREATE TABLE agents (
  rowid_key   INTEGER PRIMARY KEY,
  map_id      TEXT NOT NULL REFERENCES maps(id) ON DELETE CASCADE,
  id          TEXT NOT NULL,
  x_m         REAL NOT NULL,
  y_m         REAL NOT NULL,
  heading_rad REAL NOT NULL,
  vx_mps      REAL NOT NULL,
  vy_mps      REAL NOT NULL,
  stamp_ns    INTEGER NOT NULL,
  UNIQUE (map_id, id)
);

-- Spatial index over entity positions (R*Tree module). Agents today; later entities add their own.
CREATE VIRTUAL TABLE agents_rtree USING rtree(rowid_key, min_x, max_x, min_y, max_y);

CREATE TRIGGER agents_rtree_insert AFTER INSERT ON agents BEGIN
  INSERT INTO agents_rtree VALUES (new.rowid_key, new.x_m, new.x_m, new.y_m, new.y_m);
END;

CREATE TRIGGER agents_rtree_update AFTER UPDATE OF x_m, y_m ON agents BEGIN
  UPDATE agents_rtree SET min_x = new.x_m, max_x = new.x_m, min_y = new.y_m, max_y = new.y_m
   WHERE rowid_key = new.rowid_key;
END;

CREATE TRIGGER agents_rtree_delete AFTER DELETE ON agents BEGIN
  DELETE FROM agents_rtree WHERE rowid_key = old.rowid_key;
END;

CREATE TABLE tokens (
  id          TEXT PRIMARY KEY,
  sha256_hex  TEXT NOT NULL UNIQUE,
  role        TEXT NOT NULL CHECK (role IN ('reader', 'writer', 'admin')),
  created_ns  INTEGER NOT NULL
);
