-- Anchored features (thesis 4.3.2, SPEC §3, §4.6): a descriptor of a type (fpfh, shot, spd, orb, ...) anchored at a
-- point of the map frame [m], the keyframe it came from (forgetting a keyframe drops its features), its stamp and
-- its codeword in the type's codebook (NULL until one is built). The descriptor is a float32 blob (storage/blob_codec.h).
CREATE TABLE features (
  id           INTEGER PRIMARY KEY AUTOINCREMENT,
  map_id       TEXT NOT NULL REFERENCES maps(id) ON DELETE CASCADE,
  type         TEXT NOT NULL,
  dims         INTEGER NOT NULL,
  descriptor   BLOB NOT NULL,
  x_m          REAL NOT NULL,
  y_m          REAL NOT NULL,
  z_m          REAL NOT NULL,
  keyframe_id  INTEGER REFERENCES keyframes(id) ON DELETE CASCADE,
  stamp_ns     INTEGER NOT NULL,
  codeword     INTEGER
);
CREATE INDEX features_by_type ON features (map_id, type, id);
CREATE INDEX features_by_keyframe ON features (keyframe_id);
CREATE INDEX features_by_stamp ON features (map_id, stamp_ns);
-- The anchors in an R*Tree (id = features.id); kept in step by the triggers below, including rows removed by a
-- cascade from a map or keyframe.
CREATE VIRTUAL TABLE feature_anchors USING rtree(id, min_x, max_x, min_y, max_y, min_z, max_z);
CREATE TRIGGER features_anchor_insert AFTER INSERT ON features BEGIN
  INSERT INTO feature_anchors VALUES (new.id, new.x_m, new.x_m, new.y_m, new.y_m, new.z_m, new.z_m);
END;
CREATE TRIGGER features_anchor_delete AFTER DELETE ON features BEGIN
  DELETE FROM feature_anchors WHERE id = old.id;
END;
-- One codebook per map and type: k-means centres (float32 blob, words x dims) and how they were made.
CREATE TABLE codebooks (
  map_id       TEXT NOT NULL REFERENCES maps(id) ON DELETE CASCADE,
  type         TEXT NOT NULL,
  words        INTEGER NOT NULL,
  dims         INTEGER NOT NULL,
  seed         INTEGER NOT NULL,
  centres      BLOB NOT NULL,
  features     INTEGER NOT NULL,  -- how many features it was built from
  created_ns   INTEGER NOT NULL,
  PRIMARY KEY (map_id, type)
);
-- Trained E-SAMME models (thesis 4.2): the model blob (engine/classification/esamme.h; base models serialised by
-- OpenCV), the training request and the cross-validation report as JSON. Not per map: a classifier is knowledge.
CREATE TABLE classifiers (
  name         TEXT PRIMARY KEY,
  created_ns   INTEGER NOT NULL,
  model        BLOB NOT NULL,
  request_json TEXT NOT NULL,
  report_json  TEXT NOT NULL
);
