#pragma once
// The details of a change event between the store's typed record (storage::EventDetailsRecord, migration 0020) and
// the service's EventDetails that GET /events serves (api/event_json.cc writes its JSON): the segment that showed the
// change, an inferred move, a removal seen through, the newer model a re-analysis applied, a label event's
// distribution afterwards; each part present when it applies.
#include <cstdint>
#include <string>

#include "services/events/event_types.h"
#include "storage/connection.h"
#include "storage/event_repository.h"

namespace anchordb::services {

storage::EventDetailsRecord StoredEventDetails(const EventDetails& details);
EventDetails EventDetailsOf(const storage::EventDetailsRecord& stored);

// Inserts a 'labelled' event of `instance` (detection dialog | operator | classifier) whose details hold the
// instance's label distribution afterwards; returns its id. One place for every source of labels.
std::int64_t InsertLabelledEvent(storage::Connection& c, const std::string& map, std::int64_t instance,
                                 const std::string& label, const std::string& detection, std::int64_t stamp_ns,
                                 const std::string& explanation, const engine::LabelWeights& distribution);

}  // namespace anchordb::services
