// The frame journal of scene models (SPEC §8): what one frame changes is computed first (Step), then written in
// one transaction -- the journal row, the keyframe the frame stores, the checkpoint when one is due (which trims
// the rows it covers) -- and only then taken over by the in-memory model (FrameCommitted). Replay rebuilds a loaded
// model from its checkpoint and its rows: the frames after the checkpoint are applied again (Algorithm 1 is
// deterministic, so the layers come out byte-identical); keyframes are not stored again (they were committed with
// their frame) and the settle detector, the pixel counts and the latest depth are taken from the newest row.
#include "engine/scene/depth_image.h"
#include "services/scene/scene_service.h"
#include "services/scene/scene_service_internal.h"

namespace anchordb::services {

using namespace scene_detail;

namespace {

// Fast zstd: the raw frame is journalled on the ingest path (delta-shuffled 640x480 depth: ~1 ms, about a third).
constexpr int kJournalZstdLevel = 1;

std::vector<std::uint32_t> ShapeOf(const PinholeIntrinsics& K) {
  return {static_cast<std::uint32_t>(K.height), static_cast<std::uint32_t>(K.width)};
}

// The journalled depth and mask, decoded as when the frame arrived.
std::pair<std::vector<std::uint16_t>, std::vector<std::uint8_t>> DecodeRow(const storage::JournalFrame& row,
                                                                            const PinholeIntrinsics& K, bool with_mask) {
  const std::size_t n = static_cast<std::size_t>(K.width) * K.height;
  try {
    std::vector<std::uint16_t> depth;
    if (row.depth_codec == storage::JournalDepthCodec::kPng) {
      depth = engine::DecodeDepthPng(row.depth, "depth").pixels;
    } else {
      depth = storage::DecodeArray<std::uint16_t>(row.depth, BlobElement::kU16, n).value_or(std::vector<std::uint16_t>{});
    }
    std::vector<std::uint8_t> mask;
    if (with_mask && row.dynamic_png) mask = engine::DecodeMaskPng(*row.dynamic_png, "dynamic").pixels;
    if (depth.size() != n || (!mask.empty() && mask.size() != n)) throw Error(ErrorCode::kInternal, "its size differs from the camera");
    return {std::move(depth), std::move(mask)};
  } catch (const Error& e) {
    throw Error(ErrorCode::kInternal, "journalled frame " + std::to_string(row.frame) + " of scene " +
                                          std::to_string(row.scene_id) + " does not decode: " + e.what());
  }
}

}  // namespace

namespace scene_detail {

storage::KeyframeRecord KeyframeRecordOf(const storage::SceneRecord& scene, const PinholeIntrinsics& K,
                                         std::int64_t action_layer, KeyframeKind kind, std::int64_t stamp_ns,
                                         const std::vector<std::uint16_t>& depth_mm,
                                         const std::vector<std::uint16_t>& background_mm) {
  storage::KeyframeRecord k;
  k.map_id = scene.map_id;
  k.scene_id = scene.id;
  k.kind = NameOf(kKeyframeKindNames, kind);
  k.stamp_ns = stamp_ns;
  k.width = K.width;
  k.height = K.height;
  k.action_layer = action_layer;
  k.depth = storage::EncodeBlob(BlobElement::kU16, ShapeOf(K), storage::AsBytes(depth_mm), 3, storage::BlobFilter::kDeltaShuffle16);
  k.background = storage::EncodeBlob(BlobElement::kU16, ShapeOf(K), storage::AsBytes(background_mm), 3, storage::BlobFilter::kDeltaShuffle16);
  k.raw_bytes = static_cast<std::int64_t>(2 * 2 * depth_mm.size());
  k.stored_bytes = static_cast<std::int64_t>(k.depth.size() + k.background.size());
  return k;
}

storage::JournalFrame JournalRowOf(std::int64_t scene_id, const PinholeIntrinsics& K, const FrameInput& in,
                                   const std::vector<std::uint16_t>& depth, double scale, std::int64_t stamp_ns) {
  storage::JournalFrame row;
  row.scene_id = scene_id;
  row.stamp_ns = stamp_ns;
  row.depth_scale = scale;
  if (in.png) {
    row.depth_codec = storage::JournalDepthCodec::kPng;
    row.depth.assign(in.body);
  } else {
    row.depth_codec = storage::JournalDepthCodec::kRawZstd;
    row.depth = storage::EncodeBlob(BlobElement::kU16, ShapeOf(K), storage::AsBytes(depth), kJournalZstdLevel,
                                    storage::BlobFilter::kDeltaShuffle16);
  }
  if (in.dynamic_png) row.dynamic_png = std::string(*in.dynamic_png);
  return row;
}

}  // namespace scene_detail

SceneService::FrameStep SceneService::Step(const Model& m, const engine::SceneModelState& state,
                                           const engine::FrameCounts& counts, const std::vector<std::uint16_t>& depth,
                                           double scale, std::int64_t stamp_ns,
                                           std::optional<storage::JournalFrame> journal,
                                           const storage::SceneRecord* merged) const {
  FrameStep s;
  s.stamp_ns = stamp_ns;
  s.counts = counts;
  s.settle = m.settle;
  s.depth_mm = DepthMillimetres(depth, scale);
  const bool settled = s.settle.OnFrame(counts, limits_);  // a completed movement (3.3.4)
  if (!m.has_begin_keyframe) s.keyframe = KeyframeKind::kBegin;
  else if (settled) s.keyframe = KeyframeKind::kSettled;
  if (s.keyframe) {
    s.background_mm = ToMillimetres(state.background_m);
    s.keyframe_record = KeyframeRecordOf(m.record, m.K, m.next_action_layer, *s.keyframe, stamp_ns, s.depth_mm, s.background_mm);
    s.settle.OnKeyframe(counts.movable);
  }
  // A merge is checkpointed with its frame at once; otherwise every persist_every_frames frames.
  if (merged || m.unpersisted_frames + 1 >= limits_.persist_every_frames) {
    storage::SceneRecord base = merged ? *merged : m.record;
    base.last_frame_ns = stamp_ns;
    s.checkpoint = StateRecord(base, m.K, state);  // encoded before the write
  }
  if (journal) {
    journal->frame = state.frames;
    journal->model_after = scene_stored::EncodeModelAfter(counts, s.settle.state());
    s.journal = std::move(journal);
  }
  return s;
}

bool SceneService::WriteFrame(const Model& m, FrameStep& s, const std::function<bool(storage::Connection&)>& precondition) {
  if (!s.keyframe && !s.checkpoint && !s.journal) return true;  // journal off, nothing due: the frame lives in memory
  return store_.Write([&](storage::Connection& c) {
    if (precondition && !precondition(c)) return false;
    if (s.checkpoint) WriteCheckpoint(c, *s.checkpoint, m.record.state_version);
    if (s.keyframe) {
      s.keyframe_id = storage::InsertKeyframe(c, s.keyframe_record);
      EnqueueAnalysis(c, m, s.keyframe_id);
    }
    if (s.journal) storage::AppendJournalFrame(c, *s.journal);
    return true;
  });
}

FrameResult SceneService::FrameCommitted(Model& m, FrameStep& s) {
  m.last_counts = s.counts;
  m.settle = s.settle;
  m.last_depth_mm = std::move(s.depth_mm);
  m.record.last_frame_ns = s.stamp_ns;
  if (s.journal) m.journalled_frames = s.journal->frame;
  if (s.checkpoint) m.Persisted(*s.checkpoint);
  else ++m.unpersisted_frames;
  FrameResult out;
  out.scene_id = m.record.id;
  out.frames = m.state.frames;
  out.persisted_frames = m.DurableFrames();
  out.pixels = m.last_counts;
  if (s.keyframe) {
    m.has_begin_keyframe = true;
    out.keyframe = KeyframeStored(m, s.keyframe_id, *s.keyframe);
  }
  return out;
}

void SceneService::Replay(Model& m, const std::vector<storage::JournalFrame>& rows) const {
  const storage::JournalFrame* newest = nullptr;
  std::vector<std::uint16_t> newest_depth;
  for (const storage::JournalFrame& row : rows) {
    if (row.frame > m.state.frames + 1) {
      throw Error(ErrorCode::kInternal, "the frame journal of scene " + std::to_string(m.record.id) + " misses frame " +
                                            std::to_string(m.state.frames + 1));
    }
    const bool apply = row.frame == m.state.frames + 1;  // else the checkpoint's own last frame
    if (!apply && &row != &rows.back()) continue;
    auto [depth, mask] = DecodeRow(row, m.K, apply);
    if (apply) {
      engine::ApplyFrame(m.state, depth, row.depth_scale, mask, m.params.model);
      ++m.unpersisted_frames;
    }
    newest = &row;
    newest_depth = std::move(depth);
  }
  if (!newest) return;
  const scene_stored::ModelAfter after = scene_stored::DecodeModelAfter(newest->model_after, m.record.id, newest->frame);
  m.last_counts = after.counts;
  m.settle = engine::SettleDetector(after.settle);
  m.last_depth_mm = DepthMillimetres(newest_depth, newest->depth_scale);
  m.record.last_frame_ns = newest->stamp_ns;
  m.journalled_frames = newest->frame;
}

}  // namespace anchordb::services
