-- 0023: a furniture graph's viewpoint, parameters and graph, and each grounded description's input, become typed
-- columns and child tables instead of JSON documents. PostgreSQL form of sqlite/0023 (filled with jsonb operators, the
-- same defaults; positions 0-based).
ALTER TABLE furniture_graphs
  ADD COLUMN viewpoint_x_m DOUBLE PRECISION NOT NULL DEFAULT 0,
  ADD COLUMN viewpoint_y_m DOUBLE PRECISION NOT NULL DEFAULT 0,
  ADD COLUMN viewpoint_heading_rad DOUBLE PRECISION NOT NULL DEFAULT 0,
  ADD COLUMN grounding_model TEXT NOT NULL DEFAULT 'sequential' CHECK (grounding_model IN ('sequential', 'joint')),
  ADD COLUMN n_best INTEGER NOT NULL DEFAULT 0,
  ADD COLUMN sigma DOUBLE PRECISION NOT NULL DEFAULT 0,
  ADD COLUMN edge_max_gap_m DOUBLE PRECISION NOT NULL DEFAULT 0,
  ADD COLUMN relation_sharpness DOUBLE PRECISION NOT NULL DEFAULT 0,
  ADD COLUMN adaptation INTEGER NOT NULL DEFAULT 0,
  ADD COLUMN frame_prior TEXT NOT NULL DEFAULT 'statistical' CHECK (frame_prior IN ('uniform', 'statistical')),
  ADD COLUMN ambiguity_margin DOUBLE PRECISION NOT NULL DEFAULT 0,
  ADD COLUMN category_floor DOUBLE PRECISION NOT NULL DEFAULT 0,
  ADD COLUMN orientation_prior TEXT NOT NULL DEFAULT 'uniform' CHECK (orientation_prior IN ('uniform', 'room')),
  ADD COLUMN occupancy_layer TEXT NOT NULL DEFAULT '',
  ADD COLUMN category_count INTEGER NOT NULL DEFAULT 0;

CREATE TABLE furniture_graph_vertices (
  graph_id        BIGINT NOT NULL REFERENCES furniture_graphs(id) ON DELETE CASCADE,
  position        INTEGER NOT NULL,
  vertex_id       TEXT NOT NULL,
  x_m             DOUBLE PRECISION NOT NULL,
  y_m             DOUBLE PRECISION NOT NULL,
  extent_x_m      DOUBLE PRECISION NOT NULL,
  extent_y_m      DOUBLE PRECISION NOT NULL,
  yaw_rad         DOUBLE PRECISION NOT NULL,
  -- p(o), the initial orientation distribution (orientations in engine/grounding/knowledge.h order)
  orientation_p0  DOUBLE PRECISION NOT NULL,
  orientation_p1  DOUBLE PRECISION NOT NULL,
  orientation_p2  DOUBLE PRECISION NOT NULL,
  orientation_p3  DOUBLE PRECISION NOT NULL,
  PRIMARY KEY (graph_id, position)
);
-- p(f), the initial category distribution of each vertex (category_count rows per vertex).
CREATE TABLE furniture_graph_vertex_categories (
  graph_id        BIGINT NOT NULL REFERENCES furniture_graphs(id) ON DELETE CASCADE,
  vertex          INTEGER NOT NULL,
  category        INTEGER NOT NULL,
  p               DOUBLE PRECISION NOT NULL,
  PRIMARY KEY (graph_id, vertex, category)
);
-- The graph's undirected edges {a, b}, a < b, with p(r) from the geometry per direction (a relative to b, then b
-- relative to a; relations in engine/grounding/knowledge.h order).
CREATE TABLE furniture_graph_edges (
  graph_id        BIGINT NOT NULL REFERENCES furniture_graphs(id) ON DELETE CASCADE,
  position        INTEGER NOT NULL,
  a               INTEGER NOT NULL,
  b               INTEGER NOT NULL,
  gap_m           DOUBLE PRECISION NOT NULL,
  ab_p0           DOUBLE PRECISION NOT NULL,
  ab_p1           DOUBLE PRECISION NOT NULL,
  ab_p2           DOUBLE PRECISION NOT NULL,
  ab_p3           DOUBLE PRECISION NOT NULL,
  ba_p0           DOUBLE PRECISION NOT NULL,
  ba_p1           DOUBLE PRECISION NOT NULL,
  ba_p2           DOUBLE PRECISION NOT NULL,
  ba_p3           DOUBLE PRECISION NOT NULL,
  PRIMARY KEY (graph_id, position)
);

UPDATE furniture_graphs SET
  viewpoint_x_m = (viewpoint::jsonb #>> '{position,0}')::double precision,
  viewpoint_y_m = (viewpoint::jsonb #>> '{position,1}')::double precision,
  viewpoint_heading_rad = (viewpoint::jsonb ->> 'heading_rad')::double precision,
  grounding_model = CASE params::jsonb ->> 'model' WHEN 'joint' THEN 'joint' ELSE 'sequential' END,
  n_best = (params::jsonb ->> 'n_best')::integer,
  sigma = (params::jsonb ->> 'sigma')::double precision,
  edge_max_gap_m = (params::jsonb ->> 'edge_max_gap_m')::double precision,
  relation_sharpness = (params::jsonb ->> 'relation_sharpness')::double precision,
  adaptation = CASE WHEN (params::jsonb ->> 'adaptation')::boolean THEN 1 ELSE 0 END,
  frame_prior = CASE params::jsonb ->> 'frame_prior' WHEN 'uniform' THEN 'uniform' ELSE 'statistical' END,
  ambiguity_margin = COALESCE((params::jsonb ->> 'ambiguity_margin')::double precision, 0),
  category_floor = COALESCE((params::jsonb ->> 'category_floor')::double precision, 0),
  orientation_prior = CASE params::jsonb ->> 'orientation_prior' WHEN 'room' THEN 'room' ELSE 'uniform' END,
  occupancy_layer = COALESCE(params::jsonb ->> 'occupancy_layer', ''),
  category_count = (graph::jsonb ->> 'category_count')::integer;
INSERT INTO furniture_graph_vertices (graph_id, position, vertex_id, x_m, y_m, extent_x_m, extent_y_m, yaw_rad,
                                      orientation_p0, orientation_p1, orientation_p2, orientation_p3)
  SELECT g.id, v.n - 1, v.x ->> 'id', (v.x #>> '{position,0}')::double precision,
    (v.x #>> '{position,1}')::double precision, (v.x #>> '{extent,0}')::double precision,
    (v.x #>> '{extent,1}')::double precision, (v.x ->> 'yaw_rad')::double precision,
    COALESCE((v.x #>> '{orientations,0}')::double precision, 0.25),
    COALESCE((v.x #>> '{orientations,1}')::double precision, 0.25),
    COALESCE((v.x #>> '{orientations,2}')::double precision, 0.25),
    COALESCE((v.x #>> '{orientations,3}')::double precision, 0.25)
  FROM furniture_graphs g, jsonb_array_elements(
      CASE WHEN jsonb_typeof(g.graph::jsonb -> 'vertices') = 'array' THEN g.graph::jsonb -> 'vertices' END)
    WITH ORDINALITY AS v(x, n);
INSERT INTO furniture_graph_vertex_categories (graph_id, vertex, category, p)
  SELECT g.id, v.n - 1, f.n - 1, (f.x #>> '{}')::double precision
  FROM furniture_graphs g, jsonb_array_elements(
      CASE WHEN jsonb_typeof(g.graph::jsonb -> 'vertices') = 'array' THEN g.graph::jsonb -> 'vertices' END)
    WITH ORDINALITY AS v(x, n), jsonb_array_elements(
        CASE WHEN jsonb_typeof(v.x -> 'categories') = 'array' THEN v.x -> 'categories' END) WITH ORDINALITY AS f(x, n);
INSERT INTO furniture_graph_edges (graph_id, position, a, b, gap_m, ab_p0, ab_p1, ab_p2, ab_p3, ba_p0, ba_p1, ba_p2,
                                   ba_p3)
  SELECT g.id, e.n - 1, (e.x ->> 'a')::integer, (e.x ->> 'b')::integer, (e.x ->> 'gap_m')::double precision,
    (e.x #>> '{visual,0,0}')::double precision, (e.x #>> '{visual,0,1}')::double precision,
    (e.x #>> '{visual,0,2}')::double precision, (e.x #>> '{visual,0,3}')::double precision,
    (e.x #>> '{visual,1,0}')::double precision, (e.x #>> '{visual,1,1}')::double precision,
    (e.x #>> '{visual,1,2}')::double precision, (e.x #>> '{visual,1,3}')::double precision
  FROM furniture_graphs g, jsonb_array_elements(
      CASE WHEN jsonb_typeof(g.graph::jsonb -> 'edges') = 'array' THEN g.graph::jsonb -> 'edges' END)
    WITH ORDINALITY AS e(x, n);
ALTER TABLE furniture_graphs DROP COLUMN viewpoint, DROP COLUMN params, DROP COLUMN graph;

ALTER TABLE furniture_graph_descriptions
  ADD COLUMN input_text TEXT,
  ADD COLUMN input_located TEXT,
  ADD COLUMN input_relation TEXT,
  ADD COLUMN input_reference TEXT;
UPDATE furniture_graph_descriptions SET
  input_text = input::jsonb ->> 'text',
  input_located = input::jsonb ->> 'located',
  input_relation = input::jsonb ->> 'relation',
  input_reference = input::jsonb ->> 'reference';
ALTER TABLE furniture_graph_descriptions DROP COLUMN input;
