#pragma once
// TRANSITIONAL (issue 11): services whose interface still takes and returns JSON include this; each capability
// removes the include when its typed requests and results land, and the file is deleted with the last one.
#include "schema/json_io.h"

namespace anchordb::services {
using json::Json;
}  // namespace anchordb::services
