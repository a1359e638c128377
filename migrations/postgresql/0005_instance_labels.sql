-- 0005: an index of instance labels for "where is X?". PostgreSQL form of sqlite/0005: instances.labels (JSON text)
-- stays the truth; one trigger function keeps the table equal to its keys (jsonb_object_keys for json_each).
CREATE TABLE instance_labels (
  instance_id     BIGINT NOT NULL REFERENCES instances(id) ON DELETE CASCADE,
  map_id          TEXT NOT NULL,
  label           TEXT NOT NULL,
  PRIMARY KEY (instance_id, label)
);
CREATE INDEX instance_labels_by_label ON instance_labels (map_id, label);
CREATE FUNCTION instance_labels_follow() RETURNS trigger LANGUAGE plpgsql AS $body$
BEGIN
  IF TG_OP = 'UPDATE' THEN
    IF OLD.labels IS NOT DISTINCT FROM NEW.labels THEN
      RETURN NULL;
    END IF;
    DELETE FROM instance_labels WHERE instance_id = NEW.id;
  END IF;
  INSERT INTO instance_labels (instance_id, map_id, label)
    SELECT NEW.id, NEW.map_id, k FROM jsonb_object_keys(NEW.labels::jsonb) AS k;
  RETURN NULL;
END
$body$;
CREATE TRIGGER instance_labels_follow AFTER INSERT OR UPDATE OF labels ON instances
  FOR EACH ROW EXECUTE FUNCTION instance_labels_follow();
CREATE INDEX instances_by_kind ON instances (map_id, kind, id);
