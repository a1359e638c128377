-- The audit trail of operator and admin actions (SPEC §8): who (token id and role, or "loopback" / "cli"), what
-- (action, map, resource), when, the request id, the outcome (HTTP status) and the record before / after as JSON.
-- No foreign key to maps: entries outlive the map they name (map deletion, forgetting).
CREATE TABLE audit_log (
  id INTEGER PRIMARY KEY AUTOINCREMENT,
  time_ns INTEGER NOT NULL,
  actor TEXT NOT NULL,
  role TEXT NOT NULL,
  action TEXT NOT NULL,
  map_id TEXT NOT NULL,
  resource TEXT NOT NULL,
  request_id TEXT NOT NULL,
  status INTEGER NOT NULL,
  before_json TEXT,
  after_json TEXT
);
CREATE INDEX audit_log_by_time ON audit_log (time_ns, id);
