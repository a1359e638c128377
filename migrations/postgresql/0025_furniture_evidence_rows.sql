-- 0025: the keyframes that saw a perceived piece of furniture are rows of furniture_instance_evidence instead of a
-- JSON array in furniture_instances (issue 30: stored documents are typed records; JSON exists only in the API).
-- A keyframe named here may since have been forgotten: evidence is a record of what was seen, not a reference.
CREATE TABLE furniture_instance_evidence (
  instance_id  BIGINT NOT NULL REFERENCES furniture_instances(instance_id) ON DELETE CASCADE,
  keyframe_id  BIGINT NOT NULL,
  PRIMARY KEY (instance_id, keyframe_id)
);
-- Filled from the arrays of earlier schemas: integer entries only (as the server read them), each once.
CREATE FUNCTION anchordb_json_array(document TEXT) RETURNS jsonb LANGUAGE plpgsql IMMUTABLE AS $body$
BEGIN
  IF jsonb_typeof(document::jsonb) = 'array' THEN
    RETURN document::jsonb;
  END IF;
  RETURN '[]'::jsonb;
EXCEPTION WHEN others THEN
  RETURN '[]'::jsonb;
END
$body$;
INSERT INTO furniture_instance_evidence (instance_id, keyframe_id)
  SELECT DISTINCT f.instance_id, (e.x #>> '{}')::bigint
  FROM furniture_instances f, jsonb_array_elements(anchordb_json_array(f.evidence_json)) AS e(x)
  WHERE jsonb_typeof(e.x) = 'number' AND (e.x #>> '{}') ~ '^-?[0-9]+$'
ON CONFLICT DO NOTHING;
DROP FUNCTION anchordb_json_array(TEXT);
ALTER TABLE furniture_instances DROP COLUMN evidence_json;
