-- 0019: a grid layer's metadata becomes typed columns and child tables instead of one JSON document (issue 30:
-- stored documents are typed records; JSON exists only in the API). Columns a kind does not use are NULL. Filled
-- from the documents of earlier schemas with SQLite's JSON functions, then the document column is dropped.
-- meta_list_rows counts the layer's rows in the child table of its kind (operands, label names or ignored YAML
-- keys), so that a reader of a layer without any skips that statement.
ALTER TABLE layers ADD COLUMN width_cells INTEGER NOT NULL DEFAULT 0 CHECK (width_cells >= 0);
ALTER TABLE layers ADD COLUMN height_cells INTEGER NOT NULL DEFAULT 0 CHECK (height_cells >= 0);
ALTER TABLE layers ADD COLUMN resolution_m REAL NOT NULL DEFAULT 0.05;
ALTER TABLE layers ADD COLUMN origin_x_m REAL NOT NULL DEFAULT 0;
ALTER TABLE layers ADD COLUMN origin_y_m REAL NOT NULL DEFAULT 0;
ALTER TABLE layers ADD COLUMN origin_yaw_rad REAL NOT NULL DEFAULT 0;
-- probability and label layers: the occupancy layer they lie on
ALTER TABLE layers ADD COLUMN base_layer TEXT;
-- probability layers: the log-odds update as probabilities, and the observation updates applied
ALTER TABLE layers ADD COLUMN hit_probability REAL;
ALTER TABLE layers ADD COLUMN miss_probability REAL;
ALTER TABLE layers ADD COLUMN clamp_min_probability REAL;
ALTER TABLE layers ADD COLUMN clamp_max_probability REAL;
ALTER TABLE layers ADD COLUMN observations INTEGER;
-- fused layers: the operator over the operands (layer_fuse_operands)
ALTER TABLE layers ADD COLUMN fuse_op TEXT CHECK (fuse_op IN ('and', 'or', 'and_not', 'xor'));
-- occupancy layers: the map_server YAML as imported
ALTER TABLE layers ADD COLUMN yaml_image TEXT;
ALTER TABLE layers ADD COLUMN yaml_resolution_m REAL;
ALTER TABLE layers ADD COLUMN yaml_origin_x_m REAL;
ALTER TABLE layers ADD COLUMN yaml_origin_y_m REAL;
ALTER TABLE layers ADD COLUMN yaml_origin_yaw_rad REAL;
ALTER TABLE layers ADD COLUMN yaml_negate INTEGER;
ALTER TABLE layers ADD COLUMN yaml_occupied_thresh REAL;
ALTER TABLE layers ADD COLUMN yaml_free_thresh REAL;
ALTER TABLE layers ADD COLUMN yaml_mode TEXT CHECK (yaml_mode IN ('trinary', 'scale', 'raw'));
ALTER TABLE layers ADD COLUMN yaml_mode_given INTEGER;
ALTER TABLE layers ADD COLUMN meta_list_rows INTEGER NOT NULL DEFAULT 0;

-- A fused layer's operands, in order.
CREATE TABLE layer_fuse_operands (
  map_id      TEXT NOT NULL,
  layer       TEXT NOT NULL,
  position    INTEGER NOT NULL,
  operand     TEXT NOT NULL,
  threshold   REAL NOT NULL,
  PRIMARY KEY (map_id, layer, position),
  FOREIGN KEY (map_id, layer) REFERENCES layers(map_id, name) ON DELETE CASCADE
);
-- A label layer's names of label ids (1..65535).
CREATE TABLE layer_label_names (
  map_id      TEXT NOT NULL,
  layer       TEXT NOT NULL,
  label_id    INTEGER NOT NULL CHECK (label_id BETWEEN 1 AND 65535),
  name        TEXT NOT NULL,
  PRIMARY KEY (map_id, layer, label_id),
  FOREIGN KEY (map_id, layer) REFERENCES layers(map_id, name) ON DELETE CASCADE
);
-- An occupancy layer's YAML keys that map_server does not know, in the order of the file.
CREATE TABLE layer_ignored_yaml_keys (
  map_id      TEXT NOT NULL,
  layer       TEXT NOT NULL,
  position    INTEGER NOT NULL,
  yaml_key    TEXT NOT NULL,
  PRIMARY KEY (map_id, layer, position),
  FOREIGN KEY (map_id, layer) REFERENCES layers(map_id, name) ON DELETE CASCADE
);

UPDATE layers SET
  width_cells = json_extract(meta, '$.geometry.width_cells'),
  height_cells = json_extract(meta, '$.geometry.height_cells'),
  resolution_m = json_extract(meta, '$.geometry.resolution_m'),
  origin_x_m = json_extract(meta, '$.geometry.origin[0]'),
  origin_y_m = json_extract(meta, '$.geometry.origin[1]'),
  origin_yaw_rad = json_extract(meta, '$.geometry.origin[2]'),
  base_layer = CASE WHEN kind IN ('probability', 'label') THEN json_extract(meta, '$.base') END;
UPDATE layers SET
  hit_probability = json_extract(meta, '$.log_odds.hit'),
  miss_probability = json_extract(meta, '$.log_odds.miss'),
  clamp_min_probability = json_extract(meta, '$.log_odds.clamp_min'),
  clamp_max_probability = json_extract(meta, '$.log_odds.clamp_max'),
  observations = COALESCE(json_extract(meta, '$.observations'), 0)
WHERE kind = 'probability';
UPDATE layers SET fuse_op = json_extract(meta, '$.op') WHERE kind = 'fused';
UPDATE layers SET
  yaml_image = json_extract(meta, '$.map_server.image'),
  yaml_resolution_m = json_extract(meta, '$.map_server.resolution'),
  yaml_origin_x_m = json_extract(meta, '$.map_server.origin[0]'),
  yaml_origin_y_m = json_extract(meta, '$.map_server.origin[1]'),
  yaml_origin_yaw_rad = json_extract(meta, '$.map_server.origin[2]'),
  yaml_negate = json_extract(meta, '$.map_server.negate'),
  yaml_occupied_thresh = json_extract(meta, '$.map_server.occupied_thresh'),
  yaml_free_thresh = json_extract(meta, '$.map_server.free_thresh'),
  yaml_mode = json_extract(meta, '$.map_server.mode'),
  yaml_mode_given = COALESCE(json_extract(meta, '$.map_server.mode_given'), 0)
WHERE kind = 'occupancy';

INSERT INTO layer_fuse_operands (map_id, layer, position, operand, threshold)
  SELECT l.map_id, l.name, o.key, json_extract(o.value, '$.layer'), json_extract(o.value, '$.threshold')
  FROM layers l, json_each(l.meta, '$.operands') o WHERE l.kind = 'fused';
INSERT INTO layer_label_names (map_id, layer, label_id, name)
  SELECT l.map_id, l.name, CAST(n.key AS INTEGER), n.value FROM layers l, json_each(l.meta, '$.labels') n
  WHERE l.kind = 'label';
INSERT INTO layer_ignored_yaml_keys (map_id, layer, position, yaml_key)
  SELECT l.map_id, l.name, k.key, k.value FROM layers l, json_each(l.meta, '$.ignored_yaml_keys') k
  WHERE l.kind = 'occupancy';
UPDATE layers SET meta_list_rows =
  (SELECT count(*) FROM layer_fuse_operands o WHERE o.map_id = layers.map_id AND o.layer = layers.name) +
  (SELECT count(*) FROM layer_label_names n WHERE n.map_id = layers.map_id AND n.layer = layers.name) +
  (SELECT count(*) FROM layer_ignored_yaml_keys k WHERE k.map_id = layers.map_id AND k.layer = layers.name);
ALTER TABLE layers DROP COLUMN meta;
