#pragma once
// The details document of a change event as stored and as served (GET /events): {"segment": {centroid_m, extent_m,
// points}, "from_m", "size_similarity", "removal_event", "visibility": {confirmed, seen_through, hidden, unmeasured,
// outside}, "background_scene", "labels"}, each part present when it applies. One codec for both, so the API shows
// exactly what was recorded.
#include <cstdint>
#include <string>

#include "services/events/event_types.h"
#include "storage/connection.h"

namespace anchordb::services {

// JSON text of the document.
std::string EncodeEventDetails(const EventDetails& details);
// Throws (nlohmann parse errors, as for any corrupt stored document) when the text is not such a document.
EventDetails DecodeEventDetails(const std::string& details_json);

// Inserts a 'labelled' event of `instance` (detection dialog | operator | classifier) whose details hold the
// instance's label distribution afterwards; returns its id. One place for every source of labels.
std::int64_t InsertLabelledEvent(storage::Connection& c, const std::string& map, std::int64_t instance,
                                 const std::string& label, const std::string& detection, std::int64_t stamp_ns,
                                 const std::string& explanation, const engine::LabelWeights& distribution);

}  // namespace anchordb::services
