#pragma once
// The frame journal of scene models (migrations/0007_frame_journal.sql): every frame a model acknowledged since its
// last checkpoint, so that a model can be rebuilt after a crash. The rows are written by the scene service inside
// its frame transaction and trimmed by its checkpoints; deleting a scene model (or its map) deletes its rows by
// foreign key. Errors: anchordb::Error from storage/sqlite.h (kConflict when a (scene, frame) row exists already).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "storage/connection.h"

namespace anchordb::storage {

// How a journalled frame's depth is stored.
enum class JournalDepthCodec {
  kPng,      // the 16-bit PNG exactly as the client sent it
  kRawZstd,  // a blob (storage/blob_codec.h) of the u16 {height, width} pixels the client sent raw
};

// What the scene service needs after replaying a frame and cannot recompute from the checkpoint and the frames after
// it: the frame's pixel counts and the settle detector's state after it (engine::FrameCounts, engine::SettleState).
struct JournalModelAfter {
  std::int64_t supported_px = 0;
  std::int64_t reset_px = 0;
  std::int64_t movable_px = 0;
  std::int64_t dynamic_px = 0;
  std::int64_t no_depth_px = 0;
  std::int64_t settle_movable_at_keyframe_px = 0;
  std::int64_t settle_reset_since_keyframe_px = 0;
  std::int64_t settle_previous_movable_px = -1;
  std::int64_t settle_stable_frames = 0;
};

struct JournalFrame {
  std::int64_t scene_id = 0;
  std::int64_t frame = 0;  // the model's frame count with this frame applied (1 = its first frame)
  std::int64_t stamp_ns = 0;
  JournalDepthCodec depth_codec = JournalDepthCodec::kPng;
  std::string depth;                       // bytes as described by depth_codec
  double depth_scale = 1000.0;             // sensor units per metre the frame was applied with
  std::optional<std::string> dynamic_png;  // the 8-bit mask PNG as received
  JournalModelAfter model_after;
};

// Appends one frame (kConflict if the scene already has a row for that frame).
void AppendJournalFrame(Connection& c, const JournalFrame& frame);
// The scene's rows with frame >= from_frame, oldest first.
std::vector<JournalFrame> ReadJournal(Connection& c, std::int64_t scene_id, std::int64_t from_frame);
// Deletes the scene's rows with frame < before_frame (a checkpoint of `before_frame` frames keeps the row of its last
// frame); returns how many went.
std::int64_t TrimJournal(Connection& c, std::int64_t scene_id, std::int64_t before_frame);
// Deletes all of the scene's rows; returns how many went.
std::int64_t DeleteJournal(Connection& c, std::int64_t scene_id);
// Replaces model_after of the row (scene_id, frame); false when there is no such row.
bool UpdateJournalModelAfter(Connection& c, std::int64_t scene_id, std::int64_t frame, const JournalModelAfter& after);

// The newest row of a scene, without its images (nullopt: none).
struct JournalTail {
  std::int64_t frame = 0;
  std::int64_t stamp_ns = 0;
};
std::optional<JournalTail> LastJournalFrame(Connection& c, std::int64_t scene_id);
// Rows of one scene, or of every scene when scene_id is nullopt.
std::int64_t CountJournalFrames(Connection& c, std::optional<std::int64_t> scene_id = std::nullopt);

}  // namespace anchordb::storage
