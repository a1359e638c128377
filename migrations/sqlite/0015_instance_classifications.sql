-- 0015: what a trained classifier (E-SAMME over bags of words, issue 15 "object classification") made of an object
-- instance's segment: the class distribution of the last classification per instance. It stands beside the labels
-- people gave (instances.labels): an instance named by dialog or an operator keeps their label, and only an instance
-- nobody named takes the classifier's distribution (engine/classification/object_labels.h). segment_id and
-- keyframe_id say which points were classified; they are plain numbers, not references, so forgetting stays free to
-- drop that segment and keyframe.
CREATE TABLE instance_classifications (
  instance_id    INTEGER PRIMARY KEY REFERENCES instances(id) ON DELETE CASCADE,
  map_id         TEXT NOT NULL REFERENCES maps(id) ON DELETE CASCADE,
  classifier     TEXT NOT NULL,            -- the classifier's name when it classified
  label          TEXT NOT NULL,            -- the most probable class
  distribution   TEXT NOT NULL,            -- JSON {class: share}, every class of the classifier
  segment_id     INTEGER,
  keyframe_id    INTEGER,
  stamp_ns       INTEGER NOT NULL
);
CREATE INDEX instance_classifications_by_map ON instance_classifications (map_id, instance_id);
