#pragma once
// Lookups every capability starts with: the map a request names must exist (404 naming the field "map").
#include <string>

#include "schema/error.h"
#include "storage/repositories.h"

namespace anchordb::services {

inline void RequireMap(storage::Connection& c, const std::string& map) {
  if (!storage::FindMap(c, map)) throw Error(ErrorCode::kNotFound, "map '" + map + "' does not exist", "map");
}

}  // namespace anchordb::services
