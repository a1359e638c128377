-- 0011: one 3D occupancy tree per map (SPEC 4.9; Hornung et al.). `tree` is the full OctoMap .ot stream (log-odds
-- kept, not the lossy .bt) in the blob codec of storage/blob_codec.h (u8, zstd); `stamps` holds the per-voxel time
-- of last update as u32 rows {key_lo, key_hi, stamp_lo, stamp_hi} (packed finest-level OcTreeKey, nanoseconds).
-- `version` increases with every change (optimistic check of the service's cached tree); `format` is the layout of
-- the two blobs (1). Resolution and sensor model are the per-map parameters; max_range_m cuts the inserted rays.
CREATE TABLE octomaps (
  map_id               TEXT PRIMARY KEY REFERENCES maps(id) ON DELETE CASCADE,
  format               INTEGER NOT NULL DEFAULT 1,
  version              INTEGER NOT NULL DEFAULT 1,
  resolution_m         REAL NOT NULL,
  prob_hit             REAL NOT NULL,
  prob_miss            REAL NOT NULL,
  clamp_min            REAL NOT NULL,
  clamp_max            REAL NOT NULL,
  occupancy_threshold  REAL NOT NULL,
  max_range_m          REAL NOT NULL,
  tree                 BLOB NOT NULL,
  stamps               BLOB NOT NULL,
  base_stamp_ns        INTEGER NOT NULL DEFAULT 0,   -- the last import's time: the stamp of voxels without one
  leaves               INTEGER NOT NULL DEFAULT 0,
  occupied_leaves      INTEGER NOT NULL DEFAULT 0,
  keyframes_through    INTEGER NOT NULL DEFAULT 0,   -- octomap_from_keyframes: keyframes up to this id are in
  events_through       INTEGER NOT NULL DEFAULT 0,   -- removal events up to this id had their voxels cleared
  created_ns           INTEGER NOT NULL,
  updated_ns           INTEGER NOT NULL
);
