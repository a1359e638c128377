#pragma once
// Internal to storage/: the typed columns of a change event's details (migration 0020) and its label weights
// (event_label_weights), read and written for event_repository.cc.
#include <string>

#include "storage/connection.h"
#include "storage/event_repository.h"

namespace anchordb::storage::event_details {

// The detail columns, in the order Read and Bind take them.
extern const char* const kColumns;
constexpr int kColumnCount = 19;

// Reads the detail columns starting at column `first` (the label weights stay to be loaded: LoadLabelWeights).
// Returns the number of label weight rows to load (0 when the event has no distribution).
std::int64_t Read(const Statement& s, int first, EventDetailsRecord& details);
// Binds the detail columns to parameters first .. first + kColumnCount - 1.
void Bind(Statement& s, int first, const EventDetailsRecord& details);

void LoadLabelWeights(Connection& c, std::int64_t event_id, EventDetailsRecord& details);
void InsertLabelWeights(Connection& c, std::int64_t event_id, const EventDetailsRecord& details);

}  // namespace anchordb::storage::event_details
