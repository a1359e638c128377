-- 0003: furniture graphs and the grounding of spoken spatial descriptions (thesis 5.3).
-- A graph row keeps everything needed to continue a conversation identically after a restart: the graph as built
-- (vertices with their visual p(f), edges with their visual p(r)), the knowledge tables and parameters it was
-- built with, and the live n-best hypotheses after the last description.
CREATE TABLE furniture_graphs (
  id              INTEGER PRIMARY KEY AUTOINCREMENT,
  map_id          TEXT NOT NULL REFERENCES maps(id) ON DELETE CASCADE,
  viewpoint       TEXT NOT NULL,      -- JSON {position:[x,y], heading_rad} in the map frame
  params          TEXT NOT NULL,      -- JSON {n_best, sigma, edge_max_gap_m, relation_sharpness, adaptation, frame_prior}
  knowledge       TEXT NOT NULL,      -- JSON {categories, frame_prior}: the tables this graph grounds with
  graph           TEXT NOT NULL,      -- JSON {vertices:[{id,position,extent,yaw_rad,categories}], edges:[{a,b,gap_m,visual}]}
  created_ns      INTEGER NOT NULL,
  updated_ns      INTEGER NOT NULL,
  descriptions    INTEGER NOT NULL DEFAULT 0,  -- descriptions grounded since creation or the last reset
  state_version   INTEGER NOT NULL DEFAULT 0,  -- increases with every persisted hypothesis set
  hypotheses      BLOB NOT NULL       -- f64 {n}: the live n-best (codec: api/furniture_service.cc)
);
CREATE INDEX furniture_graphs_by_map ON furniture_graphs (map_id, id);

-- The stream of descriptions of the current conversation (emptied by a reset), as received and as understood.
CREATE TABLE furniture_graph_descriptions (
  graph_id        INTEGER NOT NULL REFERENCES furniture_graphs(id) ON DELETE CASCADE,
  seq             INTEGER NOT NULL,   -- 1, 2, ... in the order grounded
  input           TEXT NOT NULL,      -- JSON body as received ({"text"} or {"located","relation","reference"})
  located         TEXT NOT NULL,      -- category ids and relation id as understood
  relation        TEXT NOT NULL,
  reference       TEXT NOT NULL,
  created_ns      INTEGER NOT NULL,
  PRIMARY KEY (graph_id, seq)
);
