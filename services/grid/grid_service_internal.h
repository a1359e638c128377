#pragma once
// Internal to services/grid/grid_service.cc and grid_attention.cc: what both use besides the kind table.
#include <string>

#include "schema/error.h"
#include "services/grid/layer_kinds.h"
#include "storage/repositories.h"

namespace anchordb::services::grid_detail {

// A tracked person of the map; kNotFound naming it (field "agent").
inline Agent RequireAgent(storage::Connection& c, const std::string& map, const std::string& agent) {
  auto found = storage::FindAgent(c, map, agent);
  if (!found) throw Error(ErrorCode::kNotFound, "agent '" + agent + "' does not exist in map '" + map + "'", "agent");
  return std::move(*found);
}

}  // namespace anchordb::services::grid_detail
