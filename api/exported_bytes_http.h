#pragma once
// A service's exported bytes (services/common/exported_bytes.h) as an HTTP response: the content type of its format
// and its typed description as X- headers (X-Element, X-Image-Width/Height, X-Grid-Width/Height, X-Layer-Version,
// X-Scene-Frames, X-Points, X-Frame, X-Truncated, X-Octomap-Version, Content-Disposition).
#include "api/router.h"
#include "services/common/exported_bytes.h"

namespace anchordb::api {

const char* ContentTypeOf(services::BytesFormat format);
Response BytesResponse(services::ExportedLayer exported);

}  // namespace anchordb::api
