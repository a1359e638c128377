-- 0028: a per-map count of changes to its instances, their labels and their position history (issue 33). PostgreSQL
-- form of sqlite/0028: one trigger function for the three tables; a derived table, not copied by migrate-to.
CREATE TABLE map_instance_versions (
  map_id   TEXT PRIMARY KEY REFERENCES maps(id) ON DELETE CASCADE,
  version  BIGINT NOT NULL
);
CREATE FUNCTION instance_version_count() RETURNS trigger LANGUAGE plpgsql AS $body$
DECLARE
  map TEXT;
BEGIN
  IF TG_TABLE_NAME = 'instance_history' THEN
    IF TG_OP = 'DELETE' THEN
      SELECT i.map_id INTO map FROM instances i WHERE i.id = OLD.instance_id;
    ELSE
      SELECT i.map_id INTO map FROM instances i WHERE i.id = NEW.instance_id;
    END IF;
  ELSIF TG_OP = 'DELETE' THEN
    map := OLD.map_id;
  ELSE
    map := NEW.map_id;
  END IF;
  IF map IS NOT NULL AND EXISTS (SELECT 1 FROM maps WHERE id = map) THEN
    INSERT INTO map_instance_versions (map_id, version) VALUES (map, 1)
    ON CONFLICT (map_id) DO UPDATE SET version = map_instance_versions.version + 1;
  END IF;
  RETURN NULL;
END
$body$;
CREATE TRIGGER instance_version_count AFTER INSERT OR UPDATE OR DELETE ON instances
  FOR EACH ROW EXECUTE FUNCTION instance_version_count();
CREATE TRIGGER instance_version_count AFTER INSERT OR UPDATE OR DELETE ON instance_labels
  FOR EACH ROW EXECUTE FUNCTION instance_version_count();
CREATE TRIGGER instance_version_count AFTER INSERT OR UPDATE OR DELETE ON instance_history
  FOR EACH ROW EXECUTE FUNCTION instance_version_count();
