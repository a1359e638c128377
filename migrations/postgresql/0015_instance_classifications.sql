-- 0015: a trained classifier's class distribution per object instance. PostgreSQL form of sqlite/0015.
CREATE TABLE instance_classifications (
  instance_id    BIGINT PRIMARY KEY REFERENCES instances(id) ON DELETE CASCADE,
  map_id         TEXT NOT NULL REFERENCES maps(id) ON DELETE CASCADE,
  classifier     TEXT NOT NULL,
  label          TEXT NOT NULL,
  distribution   TEXT NOT NULL,
  segment_id     BIGINT,
  keyframe_id    BIGINT,
  stamp_ns       BIGINT NOT NULL
);
CREATE INDEX instance_classifications_by_map ON instance_classifications (map_id, instance_id);
-- The entries of a stored JSON object, or none when the text is not a JSON object (as SQLite's json_valid guard in
-- storage/dialect.cc: a bad document counts as no classification instead of failing a query).
CREATE FUNCTION anchordb_json_object(document TEXT) RETURNS jsonb LANGUAGE plpgsql IMMUTABLE AS $body$
BEGIN
  IF jsonb_typeof(document::jsonb) = 'object' THEN
    RETURN document::jsonb;
  END IF;
  RETURN '{}'::jsonb;
EXCEPTION WHEN others THEN
  RETURN '{}'::jsonb;
END
$body$;
