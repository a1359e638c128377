-- 0026: an instance's labels and a classification's distribution are rows instead of JSON objects in a text column
-- (issue 30). PostgreSQL form of sqlite/0026: instance_labels becomes the truth and gains the weight, its trigger
-- goes; a classification's shares are rows of instance_classification_shares.
DROP TRIGGER instance_labels_follow ON instances;
DROP FUNCTION instance_labels_follow();
ALTER TABLE instance_labels ADD COLUMN weight DOUBLE PRECISION NOT NULL DEFAULT 0;
-- Filled from the objects of earlier schemas: entries with a number; text that is not a JSON object gives none
-- (anchordb_json_object of migration 0015).
DELETE FROM instance_labels;
INSERT INTO instance_labels (instance_id, map_id, label, weight)
  SELECT i.id, i.map_id, j.key, (j.value #>> '{}')::double precision
  FROM instances i, jsonb_each(anchordb_json_object(i.labels)) AS j
  WHERE jsonb_typeof(j.value) = 'number';
ALTER TABLE instances DROP COLUMN labels;

CREATE TABLE instance_classification_shares (
  instance_id  BIGINT NOT NULL REFERENCES instance_classifications(instance_id) ON DELETE CASCADE,
  map_id       TEXT NOT NULL,
  label        TEXT NOT NULL,
  share        DOUBLE PRECISION NOT NULL,
  PRIMARY KEY (instance_id, label)
);
CREATE INDEX instance_classification_shares_by_label ON instance_classification_shares (map_id, label);
INSERT INTO instance_classification_shares (instance_id, map_id, label, share)
  SELECT k.instance_id, k.map_id, j.key, (j.value #>> '{}')::double precision
  FROM instance_classifications k, jsonb_each(anchordb_json_object(k.distribution)) AS j
  WHERE jsonb_typeof(j.value) = 'number';
ALTER TABLE instance_classifications DROP COLUMN distribution;
DROP FUNCTION anchordb_json_object(TEXT);
