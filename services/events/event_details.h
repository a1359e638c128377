#pragma once
// The details document of a change event as stored and as served (GET /events): {"segment": {centroid_m, extent_m,
// points}, "from_m", "size_similarity", "removal_event", "visibility": {confirmed, seen_through, hidden, unmeasured,
// outside}, "background_scene", "labels"}, each part present when it applies. One codec for both, so the API shows
// exactly what was recorded.
#include <string>

#include "services/events/event_types.h"

namespace anchordb::services {

// JSON text of the document.
std::string EncodeEventDetails(const EventDetails& details);
// Throws (nlohmann parse errors, as for any corrupt stored document) when the text is not such a document.
EventDetails DecodeEventDetails(const std::string& details_json);

}  // namespace anchordb::services
