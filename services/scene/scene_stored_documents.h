#pragma once
// Internal to the scene capability: what a scene model's rows store beyond their plain columns -- the merge report of
// its scenes row (a text document, encoded and decoded in scene_documents.cc alone, so that no other file of the
// capability knows its format or includes JSON; issue 30: next to become typed) and the model-after of each
// frame-journal row (typed columns since migration 0021, mapped in scene_model_after.cc). What the database holds
// and this release cannot read is kInternal.
#include <cstdint>
#include <string>

#include "engine/scene/scene_model.h"
#include "engine/scene/settle.h"
#include "services/scene/scene_types.h"
#include "storage/frame_journal.h"

namespace anchordb::services::scene_stored {

std::string EncodeMergeReport(const MergeReport& report);
// Keys that a report of an older release lacks take their defaults.
MergeReport DecodeMergeReport(const std::string& stored, std::int64_t scene_id);

// What a replay of the frame journal cannot recompute from the checkpoint and the frames after it.
struct ModelAfter {
  engine::FrameCounts counts;
  engine::SettleState settle;
};
storage::JournalModelAfter EncodeModelAfter(const engine::FrameCounts& counts, const engine::SettleState& settle);
// kInternal naming the scene and frame when a count is negative or the detector state is out of range.
ModelAfter DecodeModelAfter(const storage::JournalModelAfter& stored, std::int64_t scene_id, std::int64_t frame);

}  // namespace anchordb::services::scene_stored
