#pragma once
// The few SQL fragments that differ between the engines; every other statement is written once in the repositories.
// The spatial index: SQLite keeps an R*Tree table beside the rows (kept in step by triggers), PostgreSQL a GiST index
// on point(x, y) of the row itself (migrations/postgresql/: agents_position, scene_models_position, features_position).
#include <string>
#include <string_view>

#include "storage/connection.h"

namespace anchordb::storage {

// Where a table's points are indexed: the R*Tree table, its key column and the row's key column (SQLite), the row's
// coordinate columns (both engines; `z` empty for a 2D index).
struct SpatialIndex {
  std::string_view rtree;      // e.g. "scene_models_rtree"
  std::string_view rtree_key;  // e.g. "id"
  std::string_view row_key;    // e.g. "m.id"
  std::string_view x, y, z;    // e.g. "m.x_m", "m.y_m", "m.z_m"
};

// A condition that the row's point lies in the closed box [lo, hi], answered through the engine's spatial index.
// The bounds are SQL expressions (placeholders or columns); with plain `?` placeholders they are bound in this
// order on both engines: hi_x, hi_y, lo_x, lo_y, then (3D) hi_z, lo_z.
struct BoxBounds {
  std::string_view hi_x, hi_y, lo_x, lo_y, hi_z, lo_z;
};
std::string PointInBox(Engine engine, const SpatialIndex& index, const BoxBounds& box);

// `INSERT ... ON CONFLICT DO NOTHING` and `ON CONFLICT (...) DO UPDATE` read alike on both engines (SQLite >= 3.24),
// so no fragment is needed for them.

}  // namespace anchordb::storage
