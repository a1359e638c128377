-- 0019: a grid layer's metadata becomes typed columns and child tables instead of one JSON document. PostgreSQL
-- form of sqlite/0019 (filled with jsonb operators; positions 0-based as in SQLite's json_each).
ALTER TABLE layers
  ADD COLUMN width_cells INTEGER NOT NULL DEFAULT 0 CHECK (width_cells >= 0),
  ADD COLUMN height_cells INTEGER NOT NULL DEFAULT 0 CHECK (height_cells >= 0),
  ADD COLUMN resolution_m DOUBLE PRECISION NOT NULL DEFAULT 0.05,
  ADD COLUMN origin_x_m DOUBLE PRECISION NOT NULL DEFAULT 0,
  ADD COLUMN origin_y_m DOUBLE PRECISION NOT NULL DEFAULT 0,
  ADD COLUMN origin_yaw_rad DOUBLE PRECISION NOT NULL DEFAULT 0,
  ADD COLUMN base_layer TEXT COLLATE "C",
  ADD COLUMN hit_probability DOUBLE PRECISION,
  ADD COLUMN miss_probability DOUBLE PRECISION,
  ADD COLUMN clamp_min_probability DOUBLE PRECISION,
  ADD COLUMN clamp_max_probability DOUBLE PRECISION,
  ADD COLUMN observations BIGINT,
  ADD COLUMN fuse_op TEXT CHECK (fuse_op IN ('and', 'or', 'and_not', 'xor')),
  ADD COLUMN yaml_image TEXT,
  ADD COLUMN yaml_resolution_m DOUBLE PRECISION,
  ADD COLUMN yaml_origin_x_m DOUBLE PRECISION,
  ADD COLUMN yaml_origin_y_m DOUBLE PRECISION,
  ADD COLUMN yaml_origin_yaw_rad DOUBLE PRECISION,
  ADD COLUMN yaml_negate INTEGER,
  ADD COLUMN yaml_occupied_thresh DOUBLE PRECISION,
  ADD COLUMN yaml_free_thresh DOUBLE PRECISION,
  ADD COLUMN yaml_mode TEXT CHECK (yaml_mode IN ('trinary', 'scale', 'raw')),
  ADD COLUMN yaml_mode_given INTEGER,
  ADD COLUMN meta_list_rows INTEGER NOT NULL DEFAULT 0;

CREATE TABLE layer_fuse_operands (
  map_id      TEXT NOT NULL,
  layer       TEXT COLLATE "C" NOT NULL,
  position    INTEGER NOT NULL,
  operand     TEXT COLLATE "C" NOT NULL,
  threshold   DOUBLE PRECISION NOT NULL,
  PRIMARY KEY (map_id, layer, position),
  FOREIGN KEY (map_id, layer) REFERENCES layers(map_id, name) ON DELETE CASCADE
);
CREATE TABLE layer_label_names (
  map_id      TEXT NOT NULL,
  layer       TEXT COLLATE "C" NOT NULL,
  label_id    INTEGER NOT NULL CHECK (label_id BETWEEN 1 AND 65535),
  name        TEXT NOT NULL,
  PRIMARY KEY (map_id, layer, label_id),
  FOREIGN KEY (map_id, layer) REFERENCES layers(map_id, name) ON DELETE CASCADE
);
CREATE TABLE layer_ignored_yaml_keys (
  map_id      TEXT NOT NULL,
  layer       TEXT COLLATE "C" NOT NULL,
  position    INTEGER NOT NULL,
  yaml_key    TEXT NOT NULL,
  PRIMARY KEY (map_id, layer, position),
  FOREIGN KEY (map_id, layer) REFERENCES layers(map_id, name) ON DELETE CASCADE
);

UPDATE layers SET
  width_cells = (meta::jsonb #>> '{geometry,width_cells}')::integer,
  height_cells = (meta::jsonb #>> '{geometry,height_cells}')::integer,
  resolution_m = (meta::jsonb #>> '{geometry,resolution_m}')::double precision,
  origin_x_m = (meta::jsonb #>> '{geometry,origin,0}')::double precision,
  origin_y_m = (meta::jsonb #>> '{geometry,origin,1}')::double precision,
  origin_yaw_rad = (meta::jsonb #>> '{geometry,origin,2}')::double precision,
  base_layer = CASE WHEN kind IN ('probability', 'label') THEN meta::jsonb ->> 'base' END;
UPDATE layers SET
  hit_probability = (meta::jsonb #>> '{log_odds,hit}')::double precision,
  miss_probability = (meta::jsonb #>> '{log_odds,miss}')::double precision,
  clamp_min_probability = (meta::jsonb #>> '{log_odds,clamp_min}')::double precision,
  clamp_max_probability = (meta::jsonb #>> '{log_odds,clamp_max}')::double precision,
  observations = COALESCE((meta::jsonb ->> 'observations')::bigint, 0)
WHERE kind = 'probability';
UPDATE layers SET fuse_op = meta::jsonb ->> 'op' WHERE kind = 'fused';
UPDATE layers SET
  yaml_image = meta::jsonb #>> '{map_server,image}',
  yaml_resolution_m = (meta::jsonb #>> '{map_server,resolution}')::double precision,
  yaml_origin_x_m = (meta::jsonb #>> '{map_server,origin,0}')::double precision,
  yaml_origin_y_m = (meta::jsonb #>> '{map_server,origin,1}')::double precision,
  yaml_origin_yaw_rad = (meta::jsonb #>> '{map_server,origin,2}')::double precision,
  yaml_negate = (meta::jsonb #>> '{map_server,negate}')::integer,
  yaml_occupied_thresh = (meta::jsonb #>> '{map_server,occupied_thresh}')::double precision,
  yaml_free_thresh = (meta::jsonb #>> '{map_server,free_thresh}')::double precision,
  yaml_mode = meta::jsonb #>> '{map_server,mode}',
  yaml_mode_given = CASE WHEN (meta::jsonb #>> '{map_server,mode_given}')::boolean THEN 1 ELSE 0 END
WHERE kind = 'occupancy';

INSERT INTO layer_fuse_operands (map_id, layer, position, operand, threshold)
  SELECT l.map_id, l.name, o.n - 1, o.v ->> 'layer', (o.v ->> 'threshold')::double precision
  FROM layers l, jsonb_array_elements(
      CASE WHEN jsonb_typeof(l.meta::jsonb -> 'operands') = 'array' THEN l.meta::jsonb -> 'operands' END)
   WITH ORDINALITY AS o(v, n) WHERE l.kind = 'fused';
INSERT INTO layer_label_names (map_id, layer, label_id, name)
  SELECT l.map_id, l.name, n.key::integer, n.value FROM layers l, jsonb_each_text(
      CASE WHEN jsonb_typeof(l.meta::jsonb -> 'labels') = 'object' THEN l.meta::jsonb -> 'labels' END) n
  WHERE l.kind = 'label';
INSERT INTO layer_ignored_yaml_keys (map_id, layer, position, yaml_key)
  SELECT l.map_id, l.name, k.n - 1, k.v
  FROM layers l, jsonb_array_elements_text(
      CASE WHEN jsonb_typeof(l.meta::jsonb -> 'ignored_yaml_keys') = 'array'
        THEN l.meta::jsonb -> 'ignored_yaml_keys' END)
   WITH ORDINALITY AS k(v, n)
  WHERE l.kind = 'occupancy';
UPDATE layers SET meta_list_rows =
  (SELECT count(*) FROM layer_fuse_operands o WHERE o.map_id = layers.map_id AND o.layer = layers.name) +
  (SELECT count(*) FROM layer_label_names n WHERE n.map_id = layers.map_id AND n.layer = layers.name) +
  (SELECT count(*) FROM layer_ignored_yaml_keys k WHERE k.map_id = layers.map_id AND k.layer = layers.name);
ALTER TABLE layers DROP COLUMN meta;
