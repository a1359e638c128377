#include "storage/frame_journal.h"

#include "schema/error.h"

namespace anchordb::storage {
namespace {

const char* CodecName(JournalDepthCodec codec) { return codec == JournalDepthCodec::kPng ? "png" : "raw_zstd"; }

JournalDepthCodec CodecOf(const std::string& name) {
  if (name == "png") return JournalDepthCodec::kPng;
  if (name == "raw_zstd") return JournalDepthCodec::kRawZstd;
  throw Error(ErrorCode::kInternal, "stored journal depth codec '" + name + "' is unknown");
}

constexpr const char* kModelAfterColumns =
    "supported_px, reset_px, movable_px, dynamic_px, no_depth_px, settle_movable_at_keyframe_px, "
    "settle_reset_since_keyframe_px, settle_previous_movable_px, settle_stable_frames";

void BindModelAfter(Statement& s, int first, const JournalModelAfter& a) {
  s.Bind(first, a.supported_px).Bind(first + 1, a.reset_px).Bind(first + 2, a.movable_px).Bind(first + 3, a.dynamic_px);
  s.Bind(first + 4, a.no_depth_px).Bind(first + 5, a.settle_movable_at_keyframe_px);
  s.Bind(first + 6, a.settle_reset_since_keyframe_px).Bind(first + 7, a.settle_previous_movable_px);
  s.Bind(first + 8, a.settle_stable_frames);
}

JournalModelAfter ReadModelAfter(const Statement& s, int first) {
  return {s.Int(first),     s.Int(first + 1), s.Int(first + 2), s.Int(first + 3), s.Int(first + 4),
          s.Int(first + 5), s.Int(first + 6), s.Int(first + 7), s.Int(first + 8)};
}

}  // namespace

void AppendJournalFrame(Connection& c, const JournalFrame& f) {
  Statement s(c, std::string("INSERT INTO scene_frame_journal (scene_id, frame, stamp_ns, depth_codec, depth, depth_scale, "
                             "dynamic, ") + kModelAfterColumns + ") VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
  s.Bind(1, f.scene_id).Bind(2, f.frame).Bind(3, f.stamp_ns).Bind(4, std::string_view(CodecName(f.depth_codec)))
      .BindBlob(5, f.depth).Bind(6, f.depth_scale);
  if (f.dynamic_png) s.BindBlob(7, *f.dynamic_png);
  else s.BindNull(7);
  BindModelAfter(s, 8, f.model_after);
  s.Run();
}

std::vector<JournalFrame> ReadJournal(Connection& c, std::int64_t scene_id, std::int64_t from_frame) {
  Statement s(c, std::string("SELECT frame, stamp_ns, depth_codec, depth, depth_scale, dynamic, ") + kModelAfterColumns +
                     " FROM scene_frame_journal WHERE scene_id = ? AND frame >= ? ORDER BY frame");
  s.Bind(1, scene_id).Bind(2, from_frame);
  std::vector<JournalFrame> out;
  while (s.Step()) {
    JournalFrame f;
    f.scene_id = scene_id;
    f.frame = s.Int(0);
    f.stamp_ns = s.Int(1);
    f.depth_codec = CodecOf(s.Text(2));
    f.depth = s.Blob(3);
    f.depth_scale = s.Double(4);
    if (!s.IsNull(5)) f.dynamic_png = s.Blob(5);
    f.model_after = ReadModelAfter(s, 6);
    out.push_back(std::move(f));
  }
  return out;
}

std::int64_t TrimJournal(Connection& c, std::int64_t scene_id, std::int64_t before_frame) {
  Statement(c, "DELETE FROM scene_frame_journal WHERE scene_id = ? AND frame < ?").Bind(1, scene_id).Bind(2, before_frame).Run();
  return c.Changes();
}

std::int64_t DeleteJournal(Connection& c, std::int64_t scene_id) {
  Statement(c, "DELETE FROM scene_frame_journal WHERE scene_id = ?").Bind(1, scene_id).Run();
  return c.Changes();
}

bool UpdateJournalModelAfter(Connection& c, std::int64_t scene_id, std::int64_t frame, const JournalModelAfter& after) {
  Statement s(c, "UPDATE scene_frame_journal SET supported_px = ?, reset_px = ?, movable_px = ?, dynamic_px = ?, "
                 "no_depth_px = ?, settle_movable_at_keyframe_px = ?, settle_reset_since_keyframe_px = ?, "
                 "settle_previous_movable_px = ?, settle_stable_frames = ? WHERE scene_id = ? AND frame = ?");
  BindModelAfter(s, 1, after);
  s.Bind(10, scene_id).Bind(11, frame).Run();
  return c.Changes() == 1;
}

std::optional<JournalTail> LastJournalFrame(Connection& c, std::int64_t scene_id) {
  Statement s(c, "SELECT frame, stamp_ns FROM scene_frame_journal WHERE scene_id = ? ORDER BY frame DESC LIMIT 1");
  s.Bind(1, scene_id);
  if (!s.Step()) return std::nullopt;
  return JournalTail{s.Int(0), s.Int(1)};
}

std::int64_t CountJournalFrames(Connection& c, std::optional<std::int64_t> scene_id) {
  Statement s(c, scene_id ? "SELECT count(*) FROM scene_frame_journal WHERE scene_id = ?" : "SELECT count(*) FROM scene_frame_journal");
  if (scene_id) s.Bind(1, *scene_id);
  s.Step();
  return s.Int(0);
}

}  // namespace anchordb::storage
