-- 0005 gained the index instances_by_kind after databases had been made with an earlier form of it (commits
-- 927e65f-5283bb6): those files are at version 5 without the index and would never get it. Idempotent for the rest.
CREATE INDEX IF NOT EXISTS instances_by_kind ON instances (map_id, kind, id);
