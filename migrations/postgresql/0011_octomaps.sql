-- 0011: one 3D occupancy tree per map (SPEC 4.9). PostgreSQL form of sqlite/0011.
CREATE TABLE octomaps (
  map_id               TEXT PRIMARY KEY REFERENCES maps(id) ON DELETE CASCADE,
  format               BIGINT NOT NULL DEFAULT 1,
  version              BIGINT NOT NULL DEFAULT 1,
  resolution_m         DOUBLE PRECISION NOT NULL,
  prob_hit             DOUBLE PRECISION NOT NULL,
  prob_miss            DOUBLE PRECISION NOT NULL,
  clamp_min            DOUBLE PRECISION NOT NULL,
  clamp_max            DOUBLE PRECISION NOT NULL,
  occupancy_threshold  DOUBLE PRECISION NOT NULL,
  max_range_m          DOUBLE PRECISION NOT NULL,
  tree                 BYTEA NOT NULL,
  stamps               BYTEA NOT NULL,
  base_stamp_ns        BIGINT NOT NULL DEFAULT 0,
  leaves               BIGINT NOT NULL DEFAULT 0,
  occupied_leaves      BIGINT NOT NULL DEFAULT 0,
  keyframes_through    BIGINT NOT NULL DEFAULT 0,
  events_through       BIGINT NOT NULL DEFAULT 0,
  created_ns           BIGINT NOT NULL,
  updated_ns           BIGINT NOT NULL
);
