-- 0014: furniture the robot found itself (thesis 5.3.1). PostgreSQL form of sqlite/0014.
CREATE TABLE furniture_instances (
  instance_id    BIGINT PRIMARY KEY REFERENCES instances(id) ON DELETE CASCADE,
  map_id         TEXT NOT NULL REFERENCES maps(id) ON DELETE CASCADE,
  classifier     TEXT NOT NULL,
  min_z_m        DOUBLE PRECISION NOT NULL,
  height_m       DOUBLE PRECISION NOT NULL,
  observations   BIGINT NOT NULL DEFAULT 1,
  evidence_json  TEXT NOT NULL,
  job_id         BIGINT,
  cloud          BYTEA NOT NULL,
  created_ns     BIGINT NOT NULL,
  updated_ns     BIGINT NOT NULL
);
CREATE INDEX furniture_instances_by_map ON furniture_instances (map_id, instance_id);
