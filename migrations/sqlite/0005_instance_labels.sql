-- 0005: an index of instance labels, so "where is X?" finds the instances that carry a label without reading every
-- instance's label distribution. instances.labels (JSON) stays the truth; triggers keep this table equal to it.
CREATE TABLE instance_labels (
  instance_id     INTEGER NOT NULL REFERENCES instances(id) ON DELETE CASCADE,
  map_id          TEXT NOT NULL,
  label           TEXT NOT NULL,
  PRIMARY KEY (instance_id, label)
);
CREATE INDEX instance_labels_by_label ON instance_labels (map_id, label);
INSERT INTO instance_labels (instance_id, map_id, label)
  SELECT i.id, i.map_id, j.key FROM instances i, json_each(i.labels) j;
CREATE TRIGGER instance_labels_insert AFTER INSERT ON instances BEGIN
  INSERT INTO instance_labels (instance_id, map_id, label) SELECT new.id, new.map_id, key FROM json_each(new.labels);
END;
CREATE TRIGGER instance_labels_update AFTER UPDATE OF labels ON instances WHEN old.labels IS NOT new.labels BEGIN
  DELETE FROM instance_labels WHERE instance_id = new.id;
  INSERT INTO instance_labels (instance_id, map_id, label) SELECT new.id, new.map_id, key FROM json_each(new.labels);
END;
-- Instances by kind (where-is reads the furniture of a map, the objects with a label).
CREATE INDEX instances_by_kind ON instances (map_id, kind, id);
