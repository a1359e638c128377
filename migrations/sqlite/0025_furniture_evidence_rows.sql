-- 0025: the keyframes that saw a perceived piece of furniture are rows of furniture_instance_evidence instead of a
-- JSON array in furniture_instances (issue 30: stored documents are typed records; JSON exists only in the API).
-- A keyframe named here may since have been forgotten: evidence is a record of what was seen, not a reference.
CREATE TABLE furniture_instance_evidence (
  instance_id  INTEGER NOT NULL REFERENCES furniture_instances(instance_id) ON DELETE CASCADE,
  keyframe_id  INTEGER NOT NULL,
  PRIMARY KEY (instance_id, keyframe_id)
);
-- Filled from the arrays of earlier schemas: integer entries only (as the server read them), each once.
INSERT OR IGNORE INTO furniture_instance_evidence (instance_id, keyframe_id)
  SELECT f.instance_id, e.value
  FROM furniture_instances f, json_each(CASE WHEN json_valid(f.evidence_json) AND json_type(f.evidence_json) = 'array'
                                             THEN f.evidence_json ELSE '[]' END) e
  WHERE e.type = 'integer';
ALTER TABLE furniture_instances DROP COLUMN evidence_json;
