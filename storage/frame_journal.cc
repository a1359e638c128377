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

}  // namespace

void AppendJournalFrame(Connection& c, const JournalFrame& f) {
  Statement s(c, "INSERT INTO scene_frame_journal (scene_id, frame, stamp_ns, depth_codec, depth, depth_scale, dynamic, "
                 "model_after) VALUES (?, ?, ?, ?, ?, ?, ?, ?)");
  s.Bind(1, f.scene_id).Bind(2, f.frame).Bind(3, f.stamp_ns).Bind(4, std::string_view(CodecName(f.depth_codec)))
      .BindBlob(5, f.depth).Bind(6, f.depth_scale);
  if (f.dynamic_png) s.BindBlob(7, *f.dynamic_png);
  else s.BindNull(7);
  s.Bind(8, f.model_after_json).Run();
}

std::vector<JournalFrame> ReadJournal(Connection& c, std::int64_t scene_id, std::int64_t from_frame) {
  Statement s(c, "SELECT frame, stamp_ns, depth_codec, depth, depth_scale, dynamic, model_after FROM scene_frame_journal "
                 "WHERE scene_id = ? AND frame >= ? ORDER BY frame");
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
    f.model_after_json = s.Text(6);
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

bool UpdateJournalModelAfter(Connection& c, std::int64_t scene_id, std::int64_t frame, const std::string& model_after_json) {
  Statement(c, "UPDATE scene_frame_journal SET model_after = ? WHERE scene_id = ? AND frame = ?")
      .Bind(1, model_after_json).Bind(2, scene_id).Bind(3, frame).Run();
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
