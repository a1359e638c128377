#pragma once
// Internal to the scene capability: the two text documents a scene model's rows still store -- the merge report of
// its scenes row and the model-after of each frame-journal row -- encoded and decoded in scene_documents.cc alone,
// so that no other file of the capability knows their format or includes JSON (issue 30: they are next to become
// typed storage codecs). Unreadable stored text is kInternal: the database holds what this release cannot read.
#include <cstdint>
#include <string>

#include "engine/scene/scene_model.h"
#include "engine/scene/settle.h"
#include "services/scene/scene_types.h"

namespace anchordb::services::scene_stored {

std::string EncodeMergeReport(const MergeReport& report);
// Keys that a report of an older release lacks take their defaults.
MergeReport DecodeMergeReport(const std::string& stored, std::int64_t scene_id);

// What a replay of the frame journal cannot recompute from the checkpoint and the frames after it.
struct ModelAfter {
  engine::FrameCounts counts;
  engine::SettleState settle;
};
std::string EncodeModelAfter(const engine::FrameCounts& counts, const engine::SettleState& settle);
ModelAfter DecodeModelAfter(const std::string& stored, std::int64_t scene_id, std::int64_t frame);

}  // namespace anchordb::services::scene_stored
