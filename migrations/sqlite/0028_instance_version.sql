-- 0028: a per-map count of changes to its instances, their labels and their position history (issue 33: a keyframe
-- analysis computed outside the write transaction checks, when it writes, that nothing it read changed meanwhile;
-- with this count that check reads one row instead of every object of the map with its sample). Triggers keep it:
-- every insert, update and delete of those rows adds one (not while the map itself is being deleted). Derived
-- (storage/catalog.h): not copied by migrate-to, whose inserts count afresh on the target; no row = count 0.
CREATE TABLE map_instance_versions (
  map_id   TEXT PRIMARY KEY REFERENCES maps(id) ON DELETE CASCADE,
  version  INTEGER NOT NULL
);
CREATE TRIGGER instance_version_instance_insert AFTER INSERT ON instances BEGIN
  INSERT INTO map_instance_versions (map_id, version) SELECT id, 1 FROM maps WHERE id = new.map_id
  ON CONFLICT (map_id) DO UPDATE SET version = version + 1;
END;
CREATE TRIGGER instance_version_instance_update AFTER UPDATE ON instances BEGIN
  INSERT INTO map_instance_versions (map_id, version) SELECT id, 1 FROM maps WHERE id = new.map_id
  ON CONFLICT (map_id) DO UPDATE SET version = version + 1;
END;
CREATE TRIGGER instance_version_instance_delete AFTER DELETE ON instances BEGIN
  INSERT INTO map_instance_versions (map_id, version) SELECT id, 1 FROM maps WHERE id = old.map_id
  ON CONFLICT (map_id) DO UPDATE SET version = version + 1;
END;
CREATE TRIGGER instance_version_label_insert AFTER INSERT ON instance_labels BEGIN
  INSERT INTO map_instance_versions (map_id, version) SELECT id, 1 FROM maps WHERE id = new.map_id
  ON CONFLICT (map_id) DO UPDATE SET version = version + 1;
END;
CREATE TRIGGER instance_version_label_update AFTER UPDATE ON instance_labels BEGIN
  INSERT INTO map_instance_versions (map_id, version) SELECT id, 1 FROM maps WHERE id = new.map_id
  ON CONFLICT (map_id) DO UPDATE SET version = version + 1;
END;
CREATE TRIGGER instance_version_label_delete AFTER DELETE ON instance_labels BEGIN
  INSERT INTO map_instance_versions (map_id, version) SELECT id, 1 FROM maps WHERE id = old.map_id
  ON CONFLICT (map_id) DO UPDATE SET version = version + 1;
END;
CREATE TRIGGER instance_version_history_insert AFTER INSERT ON instance_history BEGIN
  INSERT INTO map_instance_versions (map_id, version) SELECT m.id, 1 FROM maps AS m, instances AS i WHERE i.id = new.instance_id AND m.id = i.map_id
  ON CONFLICT (map_id) DO UPDATE SET version = version + 1;
END;
CREATE TRIGGER instance_version_history_update AFTER UPDATE ON instance_history BEGIN
  INSERT INTO map_instance_versions (map_id, version) SELECT m.id, 1 FROM maps AS m, instances AS i WHERE i.id = new.instance_id AND m.id = i.map_id
  ON CONFLICT (map_id) DO UPDATE SET version = version + 1;
END;
CREATE TRIGGER instance_version_history_delete AFTER DELETE ON instance_history BEGIN
  INSERT INTO map_instance_versions (map_id, version) SELECT m.id, 1 FROM maps AS m, instances AS i WHERE i.id = old.instance_id AND m.id = i.map_id
  ON CONFLICT (map_id) DO UPDATE SET version = version + 1;
END;
