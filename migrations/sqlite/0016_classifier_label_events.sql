-- anchordb: foreign_keys off
-- 0016: a classifier's label is an event too. When object classification (migration 0015) makes a class the label
-- of an object nobody named, it records a 'labelled' event with detection 'classifier', beside those of dialog and
-- operators. SQLite cannot change the CHECK of events.detection in place, so the table is rebuilt (SQLite's
-- procedure for other kinds of table schema changes): foreign keys are off for this file (the migration runner sees
-- the first line), so dropping the old table does not cascade into event_evidence or instance_history; the runner
-- checks the keys before the commit. Ids keep their AUTOINCREMENT high-water mark: an id once served (the event
-- stream's Last-Event-ID) is never given to another event.
CREATE TABLE events_rebuilt (
  id              INTEGER PRIMARY KEY AUTOINCREMENT,
  map_id          TEXT NOT NULL REFERENCES maps(id) ON DELETE CASCADE,
  type            TEXT NOT NULL CHECK (type IN ('added', 'removed', 'moved', 'labelled')),
  -- observed: between keyframes of one observation; meanwhile: between visits (through the merge); reanalysis: an
  -- old keyframe against a newer background; dialog / operator / classifier: labels. type 'moved' is the lost-key
  -- inference.
  detection       TEXT NOT NULL CHECK (detection IN ('observed', 'meanwhile', 'reanalysis', 'dialog', 'operator',
                                                     'classifier')),
  stamp_ns        INTEGER NOT NULL,
  scene_id        INTEGER REFERENCES scene_models(id) ON DELETE SET NULL,
  action_layer    INTEGER,
  instance_id     INTEGER REFERENCES instances(id),
  segment_id      INTEGER REFERENCES segments(id),
  label           TEXT,
  explanation     TEXT NOT NULL DEFAULT '',
  details         TEXT NOT NULL DEFAULT '{}',   -- JSON: positions, matching figures
  pinned          INTEGER NOT NULL DEFAULT 0,
  created_ns      INTEGER NOT NULL
);
INSERT INTO events_rebuilt (id, map_id, type, detection, stamp_ns, scene_id, action_layer, instance_id, segment_id,
                            label, explanation, details, pinned, created_ns)
  SELECT id, map_id, type, detection, stamp_ns, scene_id, action_layer, instance_id, segment_id, label, explanation,
         details, pinned, created_ns FROM events;
DELETE FROM sqlite_sequence WHERE name = 'events_rebuilt';
INSERT INTO sqlite_sequence (name, seq) SELECT 'events_rebuilt', seq FROM sqlite_sequence WHERE name = 'events';
DROP TABLE events;
ALTER TABLE events_rebuilt RENAME TO events;
CREATE INDEX events_by_map_time ON events (map_id, stamp_ns);
CREATE INDEX events_by_instance ON events (instance_id, stamp_ns);
