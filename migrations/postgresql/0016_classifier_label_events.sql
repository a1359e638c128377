-- 0016: a classifier's label is an event too (detection 'classifier'). PostgreSQL changes the CHECK in place (SQLite
-- rebuilds the table); ids and references are untouched.
ALTER TABLE events DROP CONSTRAINT events_detection_check;
ALTER TABLE events ADD CONSTRAINT events_detection_check
  CHECK (detection IN ('observed', 'meanwhile', 'reanalysis', 'dialog', 'operator', 'classifier'));
