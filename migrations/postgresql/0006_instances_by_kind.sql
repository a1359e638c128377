-- 0006: numbered alike with sqlite/0006 (an index some SQLite files missed); the PostgreSQL 0005 made it already.
CREATE INDEX IF NOT EXISTS instances_by_kind ON instances (map_id, kind, id);
