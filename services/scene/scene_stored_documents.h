#pragma once
// Internal to the scene capability: the store's typed records of what a scene model's rows hold beyond their plain
// columns, mapped to the service's and the engine's types -- the merge report of its scene_models row (typed columns
// and child tables since migration 0022, scene_merge_record.cc) and the model-after of each frame-journal row (typed
// columns since migration 0021, scene_model_after.cc). What the database holds and this release cannot read is
// kInternal.
#include <cstdint>
#include <string>

#include "engine/scene/scene_model.h"
#include "engine/scene/settle.h"
#include "services/scene/scene_types.h"
#include "storage/frame_journal.h"
#include "storage/scene_merge_report.h"

namespace anchordb::services::scene_stored {

storage::MergeReportRecord EncodeMergeReport(const MergeReport& report);
// kInternal naming the scene for an unknown strategy or a negative count.
MergeReport DecodeMergeReport(const storage::MergeReportRecord& stored, std::int64_t scene_id);

// What a replay of the frame journal cannot recompute from the checkpoint and the frames after it.
struct ModelAfter {
  engine::FrameCounts counts;
  engine::SettleState settle;
};
storage::JournalModelAfter EncodeModelAfter(const engine::FrameCounts& counts, const engine::SettleState& settle);
// kInternal naming the scene and frame when a count is negative or the detector state is out of range.
ModelAfter DecodeModelAfter(const storage::JournalModelAfter& stored, std::int64_t scene_id, std::int64_t frame);

}  // namespace anchordb::services::scene_stored
