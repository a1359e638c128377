-- 0014: furniture the robot found itself (thesis 5.3.1, issue 16). A perceived piece is an instance of kind
-- 'furniture' (its p(f) in labels_json, footprint centre and height in position / extent, yaw) with one row here: how
-- it was classified, the keyframes that saw it, how often a segmentation found it, and the points of the segment
-- that last updated it (f32 {n, 3} blob, map frame, storage/blob_codec.h). Furniture an operator entered has no row
-- here, and a segmentation never changes it.
CREATE TABLE furniture_instances (
  instance_id    INTEGER PRIMARY KEY REFERENCES instances(id) ON DELETE CASCADE,
  map_id         TEXT NOT NULL REFERENCES maps(id) ON DELETE CASCADE,
  classifier     TEXT NOT NULL,            -- 'geometry' or 'shape_model:<name>'
  min_z_m        REAL NOT NULL,
  height_m       REAL NOT NULL,
  observations   INTEGER NOT NULL DEFAULT 1,
  evidence_json  TEXT NOT NULL,            -- keyframe ids, ascending
  job_id         INTEGER,                  -- the segmentation job that last updated it
  cloud          BLOB NOT NULL,
  created_ns     INTEGER NOT NULL,
  updated_ns     INTEGER NOT NULL
);
CREATE INDEX furniture_instances_by_map ON furniture_instances (map_id, instance_id);
