// The read side of scene models: descriptions, lists, layers and keyframes.
#include "engine/scene/depth_image.h"
#include "services/scene/scene_pose_covariance.h"
#include "services/scene/scene_service.h"
#include "services/scene/scene_service_internal.h"

namespace anchordb::services {

using namespace scene_detail;

namespace {

template <typename E>
E StoredValue(const EnumNames<E>& names, const std::string& name, const char* what) {
  const auto v = ValueOf(names, name);
  if (!v) throw Error(ErrorCode::kInternal, std::string("stored ") + what + " '" + name + "' is unknown");
  return *v;
}

SceneInfo InfoFromRecord(const storage::SceneRecord& r) {
  SceneInfo info;
  info.id = r.id;
  info.map = r.map_id;
  info.status = StoredValue(kSceneStatusNames, r.status, "scene status");
  info.camera = r.camera;
  info.X_MapCamera = r.pose;
  info.pose_covariance_map = scene_pose::FromStored(r.pose_covariance);
  info.params = StoredParams(r);
  info.merge = scene_stored::DecodeMergeReport(r.merge_report, r.id);
  info.started_ns = r.started_ns;
  info.ended_ns = r.ended_ns;
  info.last_frame_ns = r.last_frame_ns;
  info.superseded_by = r.superseded_by;
  info.persisted_frames = r.frames;
  return info;
}

storage::KeyframeRecord RequireKeyframe(storage::Connection& c, const std::string& map, std::int64_t id, bool with_images) {
  RequireMap(c, map);
  auto k = storage::FindKeyframe(c, map, id, with_images);
  if (!k) throw Error(ErrorCode::kNotFound, "keyframe " + std::to_string(id) + " does not exist in map '" + map + "'", "keyframe");
  return std::move(*k);
}

void RequireCleanable(SceneLayerKind layer, bool clean) {
  if (clean && layer != SceneLayerKind::kMovable && layer != SceneLayerKind::kDynamic) {
    throw Error(ErrorCode::kInvalidArgument, "clean applies to the movable layer only", "clean");
  }
}

}  // namespace

SceneInfo SceneService::Describe(const Model& m) const {
  SceneInfo info = InfoFromRecord(m.record);
  info.persisted_frames = m.DurableFrames();
  SceneInfo::State state;
  state.frames = m.state.frames;
  for (std::size_t i = 0; i < m.state.movable.size(); ++i) {
    state.statistics.movable_pixels += m.state.movable[i];
    state.statistics.dynamic_pixels += m.state.dynamic[i];
    state.statistics.known_background_pixels += m.state.background_m[i] > 0.0f;
  }
  info.state = state;
  return info;
}

SceneInfo SceneService::Get(const std::string& map, std::int64_t id) {
  auto [model, lock] = Lock(map, id);
  SceneInfo info = Describe(*model);
  for (const auto& k : store_.Read([&](storage::Connection& c) { return storage::ListKeyframes(c, map, id); })) {
    info.keyframes.push_back({k.id, StoredValue(kKeyframeKindNames, k.kind, "keyframe kind"), k.stamp_ns});
  }
  return info;
}

ExportedLayer SceneService::Layer(const std::string& map, std::int64_t id, SceneLayerKind layer,
                                  SceneLayerEncoding encoding, bool clean) {
  auto [model, lock] = Lock(map, id);
  RequireCleanable(layer, clean);
  const engine::SceneModelState& s = model->state;
  const int w = model->K.width, h = model->K.height;
  const bool png = encoding == SceneLayerEncoding::kPng;
  ExportedLayer out;
  out.image_width_px = w;
  out.image_height_px = h;
  out.scene_frames = s.frames;
  out.format = png ? BytesFormat::kPng : BytesFormat::kRaw;
  switch (layer) {
    case SceneLayerKind::kMovable:
    case SceneLayerKind::kDynamic: {
      std::vector<std::uint8_t> mask = layer == SceneLayerKind::kMovable ? s.movable : s.dynamic;
      if (clean && layer == SceneLayerKind::kMovable) mask = engine::CleanMovable(mask, w, h);
      out.body = png ? engine::EncodeMaskPng(mask, w, h) : std::string(storage::AsBytes(mask));
      break;
    }
    case SceneLayerKind::kStatic:
      if (!png) out.element = RawElement::kF32Metres;
      out.body = png ? engine::EncodeDepthPng(ToMillimetres(s.background_m), w, h) : std::string(storage::AsBytes(s.background_m));
      break;
    case SceneLayerKind::kReliability: {
      if (!png) {
        out.element = RawElement::kF32Weight;
        out.body = std::string(storage::AsBytes(s.weight));
        break;
      }
      std::vector<std::uint8_t> grey(s.weight.size());
      for (std::size_t i = 0; i < grey.size(); ++i) grey[i] = static_cast<std::uint8_t>(std::min(255.0f, s.weight[i]));
      out.body = engine::EncodeGreyPng(grey, w, h);
      break;
    }
  }
  return out;
}

SceneLayerSummary SceneService::LayerSummary(const std::string& map, std::int64_t id, SceneLayerKind layer, bool clean) {
  auto [model, lock] = Lock(map, id);
  RequireCleanable(layer, clean);
  const engine::SceneModelState& s = model->state;
  SceneLayerSummary out;
  out.kind = layer;
  out.width = model->K.width;
  out.height = model->K.height;
  out.frames = s.frames;
  if (layer == SceneLayerKind::kMovable || layer == SceneLayerKind::kDynamic) {
    out.cleaned = clean && layer == SceneLayerKind::kMovable;
    const std::vector<std::uint8_t> mask = out.cleaned ? engine::CleanMovable(s.movable, out.width, out.height)
                                                       : (layer == SceneLayerKind::kMovable ? s.movable : s.dynamic);
    for (auto v : mask) out.pixels += v;
    out.fraction = static_cast<double>(out.pixels) / mask.size();
  } else if (layer == SceneLayerKind::kStatic) {
    double sum = 0;
    for (float v : s.background_m) if (v > 0) sum += v, ++out.pixels;
    out.mean_depth_m = out.pixels ? sum / out.pixels : 0.0;
  } else {
    double sum = 0;
    for (float v : s.weight) out.max_weight = std::max(out.max_weight, v), sum += v;
    out.mean_weight = sum / s.weight.size();
  }
  return out;
}

std::vector<SceneInfo> SceneService::List(const std::string& map, const SceneListFilter& filter) {
  storage::SceneFilter f;
  f.near_m = filter.near_m;
  f.radius_m = filter.radius_m;
  if (filter.status) f.status = NameOf(kSceneStatusNames, *filter.status);
  f.limit = filter.limit;
  return store_.Read([&](storage::Connection& c) {
    RequireMap(c, map);
    std::vector<SceneInfo> out;
    for (const auto& r : storage::ListScenes(c, map, f)) {
      out.push_back(InfoFromRecord(r));
      if (r.status != "observing") continue;
      if (const auto tail = storage::LastJournalFrame(c, r.id)) {  // acknowledged frames since the checkpoint
        out.back().persisted_frames = std::max(r.frames, tail->frame);
        out.back().last_frame_ns = std::max(r.last_frame_ns.value_or(tail->stamp_ns), tail->stamp_ns);
      }
    }
    return out;
  });
}

KeyframeInfo SceneService::GetKeyframe(const std::string& map, std::int64_t id) {
  const storage::KeyframeRecord k = store_.Read([&](storage::Connection& c) { return RequireKeyframe(c, map, id, false); });
  return {k.id, k.scene_id, StoredValue(kKeyframeKindNames, k.kind, "keyframe kind"), k.stamp_ns, k.width, k.height,
          k.raw_bytes, k.stored_bytes, static_cast<double>(k.stored_bytes) / static_cast<double>(k.raw_bytes), k.pinned};
}

ExportedLayer SceneService::KeyframeImage(const std::string& map, std::int64_t id, KeyframeImageKind which) {
  const storage::KeyframeRecord k = store_.Read([&](storage::Connection& c) { return RequireKeyframe(c, map, id, true); });
  const std::size_t n = static_cast<std::size_t>(k.width) * k.height;
  const auto pixels = DecodeAs<std::uint16_t>(which == KeyframeImageKind::kDepth ? k.depth : k.background, BlobElement::kU16, n);
  ExportedLayer out;
  out.format = BytesFormat::kPng;
  out.body = engine::EncodeDepthPng(pixels, k.width, k.height);
  return out;
}

}  // namespace anchordb::services
