-- 0026: an instance's labels and a classification's distribution are rows instead of JSON objects in a text column
-- (issue 30: stored documents are typed records; JSON exists only in the API). instance_labels, until now an index
-- that triggers kept equal to instances.labels, becomes the truth and gains the weight; the triggers go. A
-- classification's shares are rows of instance_classification_shares (map_id copied, so that instances?label= finds
-- the instances a classifier gives that label through an index).
DROP TRIGGER instance_labels_insert;
DROP TRIGGER instance_labels_update;
ALTER TABLE instance_labels ADD COLUMN weight REAL NOT NULL DEFAULT 0;
-- Filled from the objects of earlier schemas: entries with a number (as the server read them); text that is not a
-- JSON object gives no labels.
DELETE FROM instance_labels;
INSERT OR IGNORE INTO instance_labels (instance_id, map_id, label, weight)
  SELECT i.id, i.map_id, j.key, j.value
  FROM instances i, json_each(CASE WHEN json_valid(i.labels) AND json_type(i.labels) = 'object'
                                   THEN i.labels ELSE '{}' END) j
  WHERE j.type IN ('integer', 'real');
ALTER TABLE instances DROP COLUMN labels;

CREATE TABLE instance_classification_shares (
  instance_id  INTEGER NOT NULL REFERENCES instance_classifications(instance_id) ON DELETE CASCADE,
  map_id       TEXT NOT NULL,
  label        TEXT NOT NULL,
  share        REAL NOT NULL,
  PRIMARY KEY (instance_id, label)
);
CREATE INDEX instance_classification_shares_by_label ON instance_classification_shares (map_id, label);
INSERT OR IGNORE INTO instance_classification_shares (instance_id, map_id, label, share)
  SELECT k.instance_id, k.map_id, j.key, j.value
  FROM instance_classifications k, json_each(CASE WHEN json_valid(k.distribution) AND json_type(k.distribution) = 'object'
                                                  THEN k.distribution ELSE '{}' END) j
  WHERE j.type IN ('integer', 'real');
ALTER TABLE instance_classifications DROP COLUMN distribution;
