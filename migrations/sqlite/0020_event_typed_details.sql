-- 0020: a change event's details become typed columns and a child table instead of one JSON document (issue 30:
-- stored documents are typed records; JSON exists only in the API). Each part of the old document is a group of
-- columns that is NULL as a whole when the part does not apply: the segment that showed the change (present when
-- segment_points is not NULL), an inferred move (moved_from_x_m), a removal seen through (visibility_outside), the
-- newer model whose background a re-analysis applied (background_scene), and a label event's distribution
-- afterwards (event_label_weights; label_weight_rows counts its rows, NULL when the event has none). Filled from the
-- documents of earlier schemas with SQLite's JSON functions, then the document column is dropped.
ALTER TABLE events ADD COLUMN segment_centroid_x_m REAL;
ALTER TABLE events ADD COLUMN segment_centroid_y_m REAL;
ALTER TABLE events ADD COLUMN segment_centroid_z_m REAL;
ALTER TABLE events ADD COLUMN segment_extent_x_m REAL;
ALTER TABLE events ADD COLUMN segment_extent_y_m REAL;
ALTER TABLE events ADD COLUMN segment_extent_z_m REAL;
ALTER TABLE events ADD COLUMN segment_points INTEGER;
ALTER TABLE events ADD COLUMN moved_from_x_m REAL;
ALTER TABLE events ADD COLUMN moved_from_y_m REAL;
ALTER TABLE events ADD COLUMN moved_from_z_m REAL;
ALTER TABLE events ADD COLUMN move_size_similarity REAL;
ALTER TABLE events ADD COLUMN move_removal_event INTEGER;
ALTER TABLE events ADD COLUMN visibility_outside INTEGER;
ALTER TABLE events ADD COLUMN visibility_confirmed INTEGER;
ALTER TABLE events ADD COLUMN visibility_seen_through INTEGER;
ALTER TABLE events ADD COLUMN visibility_hidden INTEGER;
ALTER TABLE events ADD COLUMN visibility_unmeasured INTEGER;
ALTER TABLE events ADD COLUMN background_scene INTEGER;
ALTER TABLE events ADD COLUMN label_weight_rows INTEGER;

CREATE TABLE event_label_weights (
  event_id    INTEGER NOT NULL REFERENCES events(id) ON DELETE CASCADE,
  label       TEXT NOT NULL,
  weight      REAL NOT NULL,
  PRIMARY KEY (event_id, label)
);

UPDATE events SET
  segment_centroid_x_m = json_extract(details, '$.segment.centroid_m[0]'),
  segment_centroid_y_m = json_extract(details, '$.segment.centroid_m[1]'),
  segment_centroid_z_m = json_extract(details, '$.segment.centroid_m[2]'),
  segment_extent_x_m = json_extract(details, '$.segment.extent_m[0]'),
  segment_extent_y_m = json_extract(details, '$.segment.extent_m[1]'),
  segment_extent_z_m = json_extract(details, '$.segment.extent_m[2]'),
  segment_points = json_extract(details, '$.segment.points')
WHERE json_type(details, '$.segment') = 'object';
UPDATE events SET
  moved_from_x_m = json_extract(details, '$.from_m[0]'),
  moved_from_y_m = json_extract(details, '$.from_m[1]'),
  moved_from_z_m = json_extract(details, '$.from_m[2]'),
  move_size_similarity = COALESCE(json_extract(details, '$.size_similarity'), 0),
  move_removal_event = json_extract(details, '$.removal_event')
WHERE json_type(details, '$.from_m') = 'array';
UPDATE events SET
  visibility_outside = json_extract(details, '$.visibility.outside'),
  visibility_confirmed = json_extract(details, '$.visibility.confirmed'),
  visibility_seen_through = json_extract(details, '$.visibility.seen_through'),
  visibility_hidden = json_extract(details, '$.visibility.hidden'),
  visibility_unmeasured = json_extract(details, '$.visibility.unmeasured')
WHERE json_type(details, '$.visibility') = 'object';
UPDATE events SET background_scene = json_extract(details, '$.background_scene');
INSERT INTO event_label_weights (event_id, label, weight)
  SELECT e.id, l.key, l.value FROM events e, json_each(e.details, '$.labels') l
  WHERE json_type(e.details, '$.labels') = 'object' AND l.type IN ('integer', 'real');
UPDATE events SET label_weight_rows = (SELECT count(*) FROM event_label_weights w WHERE w.event_id = events.id)
WHERE json_type(details, '$.labels') = 'object';
ALTER TABLE events DROP COLUMN details;
