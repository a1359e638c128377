-- 0020: a change event's details become typed columns and a child table instead of one JSON document. PostgreSQL
-- form of sqlite/0020 (filled with jsonb operators).
ALTER TABLE events
  ADD COLUMN segment_centroid_x_m DOUBLE PRECISION,
  ADD COLUMN segment_centroid_y_m DOUBLE PRECISION,
  ADD COLUMN segment_centroid_z_m DOUBLE PRECISION,
  ADD COLUMN segment_extent_x_m DOUBLE PRECISION,
  ADD COLUMN segment_extent_y_m DOUBLE PRECISION,
  ADD COLUMN segment_extent_z_m DOUBLE PRECISION,
  ADD COLUMN segment_points BIGINT,
  ADD COLUMN moved_from_x_m DOUBLE PRECISION,
  ADD COLUMN moved_from_y_m DOUBLE PRECISION,
  ADD COLUMN moved_from_z_m DOUBLE PRECISION,
  ADD COLUMN move_size_similarity DOUBLE PRECISION,
  ADD COLUMN move_removal_event BIGINT,
  ADD COLUMN visibility_outside BIGINT,
  ADD COLUMN visibility_confirmed BIGINT,
  ADD COLUMN visibility_seen_through BIGINT,
  ADD COLUMN visibility_hidden BIGINT,
  ADD COLUMN visibility_unmeasured BIGINT,
  ADD COLUMN background_scene BIGINT,
  ADD COLUMN label_weight_rows BIGINT;

CREATE TABLE event_label_weights (
  event_id    BIGINT NOT NULL REFERENCES events(id) ON DELETE CASCADE,
  label       TEXT COLLATE "C" NOT NULL,
  weight      DOUBLE PRECISION NOT NULL,
  PRIMARY KEY (event_id, label)
);

UPDATE events SET
  segment_centroid_x_m = (details::jsonb #>> '{segment,centroid_m,0}')::double precision,
  segment_centroid_y_m = (details::jsonb #>> '{segment,centroid_m,1}')::double precision,
  segment_centroid_z_m = (details::jsonb #>> '{segment,centroid_m,2}')::double precision,
  segment_extent_x_m = (details::jsonb #>> '{segment,extent_m,0}')::double precision,
  segment_extent_y_m = (details::jsonb #>> '{segment,extent_m,1}')::double precision,
  segment_extent_z_m = (details::jsonb #>> '{segment,extent_m,2}')::double precision,
  segment_points = (details::jsonb #>> '{segment,points}')::bigint
WHERE jsonb_typeof(details::jsonb -> 'segment') = 'object';
UPDATE events SET
  moved_from_x_m = (details::jsonb #>> '{from_m,0}')::double precision,
  moved_from_y_m = (details::jsonb #>> '{from_m,1}')::double precision,
  moved_from_z_m = (details::jsonb #>> '{from_m,2}')::double precision,
  move_size_similarity = COALESCE((details::jsonb ->> 'size_similarity')::double precision, 0),
  move_removal_event = (details::jsonb ->> 'removal_event')::bigint
WHERE jsonb_typeof(details::jsonb -> 'from_m') = 'array';
UPDATE events SET
  visibility_outside = (details::jsonb #>> '{visibility,outside}')::bigint,
  visibility_confirmed = (details::jsonb #>> '{visibility,confirmed}')::bigint,
  visibility_seen_through = (details::jsonb #>> '{visibility,seen_through}')::bigint,
  visibility_hidden = (details::jsonb #>> '{visibility,hidden}')::bigint,
  visibility_unmeasured = (details::jsonb #>> '{visibility,unmeasured}')::bigint
WHERE jsonb_typeof(details::jsonb -> 'visibility') = 'object';
UPDATE events SET background_scene = (details::jsonb ->> 'background_scene')::bigint;
INSERT INTO event_label_weights (event_id, label, weight)
  SELECT e.id, l.key, (l.value #>> '{}')::double precision FROM events e, jsonb_each(
      CASE WHEN jsonb_typeof(e.details::jsonb -> 'labels') = 'object' THEN e.details::jsonb -> 'labels' END) l
  WHERE jsonb_typeof(e.details::jsonb -> 'labels') = 'object' AND jsonb_typeof(l.value) = 'number';
UPDATE events SET label_weight_rows = (SELECT count(*) FROM event_label_weights w WHERE w.event_id = events.id)
WHERE jsonb_typeof(details::jsonb -> 'labels') = 'object';
ALTER TABLE events DROP COLUMN details;
