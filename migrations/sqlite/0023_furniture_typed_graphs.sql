-- 0023: a furniture graph's viewpoint, parameters and graph, and each grounded description's input, become typed
-- columns and child tables instead of JSON documents (issue 30: stored documents are typed records; JSON exists only
-- in the API). The knowledge tables a graph grounds with stay text in the engine's knowledge format
-- (engine/grounding/knowledge.h): the operator's tables completed with the built-in ones when the graph was made.
-- Filled from the documents of earlier schemas with SQLite's JSON functions and the defaults the server applied to a
-- graph of an older release, then the document columns are dropped.
ALTER TABLE furniture_graphs ADD COLUMN viewpoint_x_m REAL NOT NULL DEFAULT 0;
ALTER TABLE furniture_graphs ADD COLUMN viewpoint_y_m REAL NOT NULL DEFAULT 0;
ALTER TABLE furniture_graphs ADD COLUMN viewpoint_heading_rad REAL NOT NULL DEFAULT 0;
ALTER TABLE furniture_graphs ADD COLUMN grounding_model TEXT NOT NULL DEFAULT 'sequential'
  CHECK (grounding_model IN ('sequential', 'joint'));
ALTER TABLE furniture_graphs ADD COLUMN n_best INTEGER NOT NULL DEFAULT 0;
ALTER TABLE furniture_graphs ADD COLUMN sigma REAL NOT NULL DEFAULT 0;
ALTER TABLE furniture_graphs ADD COLUMN edge_max_gap_m REAL NOT NULL DEFAULT 0;
ALTER TABLE furniture_graphs ADD COLUMN relation_sharpness REAL NOT NULL DEFAULT 0;
ALTER TABLE furniture_graphs ADD COLUMN adaptation INTEGER NOT NULL DEFAULT 0;
ALTER TABLE furniture_graphs ADD COLUMN frame_prior TEXT NOT NULL DEFAULT 'statistical'
  CHECK (frame_prior IN ('uniform', 'statistical'));
ALTER TABLE furniture_graphs ADD COLUMN ambiguity_margin REAL NOT NULL DEFAULT 0;
ALTER TABLE furniture_graphs ADD COLUMN category_floor REAL NOT NULL DEFAULT 0;
ALTER TABLE furniture_graphs ADD COLUMN orientation_prior TEXT NOT NULL DEFAULT 'uniform'
  CHECK (orientation_prior IN ('uniform', 'room'));
ALTER TABLE furniture_graphs ADD COLUMN occupancy_layer TEXT NOT NULL DEFAULT '';
ALTER TABLE furniture_graphs ADD COLUMN category_count INTEGER NOT NULL DEFAULT 0;

CREATE TABLE furniture_graph_vertices (
  graph_id        INTEGER NOT NULL REFERENCES furniture_graphs(id) ON DELETE CASCADE,
  position        INTEGER NOT NULL,
  vertex_id       TEXT NOT NULL,
  x_m             REAL NOT NULL,
  y_m             REAL NOT NULL,
  extent_x_m      REAL NOT NULL,
  extent_y_m      REAL NOT NULL,
  yaw_rad         REAL NOT NULL,
  -- p(o), the initial orientation distribution (orientations in engine/grounding/knowledge.h order)
  orientation_p0  REAL NOT NULL,
  orientation_p1  REAL NOT NULL,
  orientation_p2  REAL NOT NULL,
  orientation_p3  REAL NOT NULL,
  PRIMARY KEY (graph_id, position)
);
-- p(f), the initial category distribution of each vertex (category_count rows per vertex).
CREATE TABLE furniture_graph_vertex_categories (
  graph_id        INTEGER NOT NULL REFERENCES furniture_graphs(id) ON DELETE CASCADE,
  vertex          INTEGER NOT NULL,
  category        INTEGER NOT NULL,
  p               REAL NOT NULL,
  PRIMARY KEY (graph_id, vertex, category)
);
-- The graph's undirected edges {a, b}, a < b, with p(r) from the geometry per direction (a relative to b, then b
-- relative to a; relations in engine/grounding/knowledge.h order).
CREATE TABLE furniture_graph_edges (
  graph_id        INTEGER NOT NULL REFERENCES furniture_graphs(id) ON DELETE CASCADE,
  position        INTEGER NOT NULL,
  a               INTEGER NOT NULL,
  b               INTEGER NOT NULL,
  gap_m           REAL NOT NULL,
  ab_p0           REAL NOT NULL,
  ab_p1           REAL NOT NULL,
  ab_p2           REAL NOT NULL,
  ab_p3           REAL NOT NULL,
  ba_p0           REAL NOT NULL,
  ba_p1           REAL NOT NULL,
  ba_p2           REAL NOT NULL,
  ba_p3           REAL NOT NULL,
  PRIMARY KEY (graph_id, position)
);

UPDATE furniture_graphs SET
  viewpoint_x_m = json_extract(viewpoint, '$.position[0]'),
  viewpoint_y_m = json_extract(viewpoint, '$.position[1]'),
  viewpoint_heading_rad = json_extract(viewpoint, '$.heading_rad'),
  grounding_model = CASE json_extract(params, '$.model') WHEN 'joint' THEN 'joint' ELSE 'sequential' END,
  n_best = json_extract(params, '$.n_best'),
  sigma = json_extract(params, '$.sigma'),
  edge_max_gap_m = json_extract(params, '$.edge_max_gap_m'),
  relation_sharpness = json_extract(params, '$.relation_sharpness'),
  adaptation = COALESCE(json_extract(params, '$.adaptation'), 0),
  frame_prior = CASE json_extract(params, '$.frame_prior') WHEN 'uniform' THEN 'uniform' ELSE 'statistical' END,
  ambiguity_margin = COALESCE(json_extract(params, '$.ambiguity_margin'), 0),
  category_floor = COALESCE(json_extract(params, '$.category_floor'), 0),
  orientation_prior = CASE json_extract(params, '$.orientation_prior') WHEN 'room' THEN 'room' ELSE 'uniform' END,
  occupancy_layer = COALESCE(json_extract(params, '$.occupancy_layer'), ''),
  category_count = json_extract(graph, '$.category_count');
-- A graph stored before issue 17 started from the uniform p(o) and did not store it.
INSERT INTO furniture_graph_vertices (graph_id, position, vertex_id, x_m, y_m, extent_x_m, extent_y_m, yaw_rad,
                                      orientation_p0, orientation_p1, orientation_p2, orientation_p3)
  SELECT g.id, v.key, json_extract(v.value, '$.id'), json_extract(v.value, '$.position[0]'),
    json_extract(v.value, '$.position[1]'), json_extract(v.value, '$.extent[0]'), json_extract(v.value, '$.extent[1]'),
    json_extract(v.value, '$.yaw_rad'), COALESCE(json_extract(v.value, '$.orientations[0]'), 0.25),
    COALESCE(json_extract(v.value, '$.orientations[1]'), 0.25),
    COALESCE(json_extract(v.value, '$.orientations[2]'), 0.25),
    COALESCE(json_extract(v.value, '$.orientations[3]'), 0.25)
  FROM furniture_graphs g, json_each(g.graph, '$.vertices') v;
INSERT INTO furniture_graph_vertex_categories (graph_id, vertex, category, p)
  SELECT g.id, v.key, f.key, f.value
  FROM furniture_graphs g, json_each(g.graph, '$.vertices') v, json_each(v.value, '$.categories') f;
INSERT INTO furniture_graph_edges (graph_id, position, a, b, gap_m, ab_p0, ab_p1, ab_p2, ab_p3, ba_p0, ba_p1, ba_p2,
                                   ba_p3)
  SELECT g.id, e.key, json_extract(e.value, '$.a'), json_extract(e.value, '$.b'), json_extract(e.value, '$.gap_m'),
    json_extract(e.value, '$.visual[0][0]'), json_extract(e.value, '$.visual[0][1]'),
    json_extract(e.value, '$.visual[0][2]'), json_extract(e.value, '$.visual[0][3]'),
    json_extract(e.value, '$.visual[1][0]'), json_extract(e.value, '$.visual[1][1]'),
    json_extract(e.value, '$.visual[1][2]'), json_extract(e.value, '$.visual[1][3]')
  FROM furniture_graphs g, json_each(g.graph, '$.edges') e;
ALTER TABLE furniture_graphs DROP COLUMN viewpoint;
ALTER TABLE furniture_graphs DROP COLUMN params;
ALTER TABLE furniture_graphs DROP COLUMN graph;

-- A description as received: its text, or the located category, relation and reference category it named (input_text
-- NULL). located / relation / reference keep what was understood.
ALTER TABLE furniture_graph_descriptions ADD COLUMN input_text TEXT;
ALTER TABLE furniture_graph_descriptions ADD COLUMN input_located TEXT;
ALTER TABLE furniture_graph_descriptions ADD COLUMN input_relation TEXT;
ALTER TABLE furniture_graph_descriptions ADD COLUMN input_reference TEXT;
UPDATE furniture_graph_descriptions SET
  input_text = json_extract(input, '$.text'),
  input_located = json_extract(input, '$.located'),
  input_relation = json_extract(input, '$.relation'),
  input_reference = json_extract(input, '$.reference');
ALTER TABLE furniture_graph_descriptions DROP COLUMN input;
