-- 0013: trained 3D shape models of furniture (thesis 4.1). PostgreSQL form of sqlite/0013.
CREATE TABLE shape_models (
  name         TEXT COLLATE "C" PRIMARY KEY,
  created_ns   BIGINT NOT NULL,
  model        BYTEA NOT NULL,
  request_json TEXT NOT NULL,
  report_json  TEXT NOT NULL
);
