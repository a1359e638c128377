#include "api/scene_service.h"

#include <chrono>
#include <cmath>

#include "engine/scene/depth_image.h"
#include "engine/scene/merge.h"
#include "engine/scene/projection.h"
#include "schema/error.h"
#include "storage/blob_codec.h"

namespace anchordb::api {

using storage::BlobElement;

namespace {

std::int64_t NowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}

Json IntrinsicsJson(const PinholeIntrinsics& K) {
  return {{"width", K.width}, {"height", K.height}, {"fx", K.fx}, {"fy", K.fy}, {"cx", K.cx}, {"cy", K.cy}};
}

PinholeIntrinsics ParseIntrinsics(const Json& j, int max_side) {
  if (!j.is_object()) throw Error(ErrorCode::kInvalidArgument, "camera must be an object {width,height,fx,fy,cx,cy}", "camera");
  json::RejectUnknownKeys(j, {"width", "height", "fx", "fy", "cx", "cy"}, "camera");
  PinholeIntrinsics K;
  const double w = json::RequireFiniteNumber(j, "width", "camera"), h = json::RequireFiniteNumber(j, "height", "camera");
  if (w != std::floor(w) || h != std::floor(h)) throw Error(ErrorCode::kInvalidArgument, "camera width/height must be integers", "camera.width");
  if (w < 1 || h < 1 || w > max_side || h > max_side) {
    throw Error(ErrorCode::kUnprocessable, "camera width and height must be in [1, " + std::to_string(max_side) + "]", "camera.width");
  }
  K.width = static_cast<int>(w);
  K.height = static_cast<int>(h);
  K.fx = json::RequireFiniteNumber(j, "fx", "camera");
  K.fy = json::RequireFiniteNumber(j, "fy", "camera");
  K.cx = json::RequireFiniteNumber(j, "cx", "camera");
  K.cy = json::RequireFiniteNumber(j, "cy", "camera");
  if (K.fx <= 0 || K.fy <= 0) throw Error(ErrorCode::kUnprocessable, "camera fx and fy must be positive", "camera.fx");
  return K;
}

PinholeIntrinsics IntrinsicsFromJson(const Json& j) {
  return {j.at("width").get<int>(), j.at("height").get<int>(), j.at("fx").get<double>(), j.at("fy").get<double>(),
          j.at("cx").get<double>(), j.at("cy").get<double>()};
}

double ParseDepthScale(double v, const std::string& field) {
  if (!(v > 0.0) || v > 1e6) throw Error(ErrorCode::kUnprocessable, "depth_scale must be in (0, 1e6] units per metre", field);
  return v;
}

std::string EncodeF32(const std::vector<float>& v, int w, int h) {
  return storage::EncodeBlob(BlobElement::kF32, {static_cast<std::uint32_t>(h), static_cast<std::uint32_t>(w)},
                             storage::AsBytes(v), 1);
}

template <typename T>
std::vector<T> DecodeAs(const std::string& blob, BlobElement element, std::size_t count) {
  const auto d = storage::DecodeBlob(blob);
  if (d.element != element || d.bytes.size() != count * sizeof(T)) {
    throw Error(ErrorCode::kInternal, "stored scene state does not match the model's camera");
  }
  std::vector<T> out(count);
  std::memcpy(out.data(), d.bytes.data(), d.bytes.size());
  return out;
}

std::vector<std::uint16_t> ToMillimetres(const std::vector<float>& metres) {
  std::vector<std::uint16_t> mm(metres.size());
  for (std::size_t i = 0; i < metres.size(); ++i) {
    mm[i] = static_cast<std::uint16_t>(std::clamp(std::lround(metres[i] * 1000.0f), 0L, 65535L));
  }
  return mm;
}

}  // namespace

struct SceneService::Model {
  std::mutex mutex;
  storage::SceneRecord record;  // state blobs not kept here
  PinholeIntrinsics K;
  engine::SceneModelParams params;
  double depth_scale = 1000.0;
  engine::SceneModelState state;
  int unpersisted_frames = 0;
  std::vector<std::uint16_t> last_depth_mm;  // the latest frame, for keyframes
  bool has_begin_keyframe = false;
  engine::FrameCounts last_counts;
  std::int64_t next_action_layer = 0;  // the layer the next keyframe opens
  // Settled-movement detection (SceneLimits::settle_*).
  std::int64_t movable_at_keyframe = 0;
  std::int64_t reset_since_keyframe = 0;
  std::int64_t previous_movable = -1;
  int stable_frames = 0;
};

SceneService::SceneService(storage::Store& store, SceneLimits limits, MergeSettings merge)
    : store_(store), limits_(limits), merge_(merge) {}

SceneService::~SceneService() {
  try {
    PersistAll();
  } catch (...) {
    // Shutdown must not throw; an unpersisted tail is lost exactly as on a crash.
  }
}

Json SceneService::Open(const std::string& map, const Json& body) {
  json::RejectUnknownKeys(body, {"camera", "pose", "params", "merge", "stamp"});
  const PinholeIntrinsics K = ParseIntrinsics(json::Require(body, "camera"), limits_.max_image_side);
  const Pose3 pose = json::AsPose3(json::Require(body, "pose"), "pose");
  engine::SceneModelParams params;
  double depth_scale = 1000.0;
  std::string strategy = "algorithm2";
  if (body.contains("params")) {
    const Json& p = body["params"];
    if (!p.is_object()) throw Error(ErrorCode::kInvalidArgument, "params must be an object", "params");
    json::RejectUnknownKeys(p, {"beta", "dynamic_mode", "depth_scale", "merge_strategy"}, "params");
    params.beta = json::FiniteNumberOr(p, "beta", params.beta, "params");
    if (!(params.beta > 0.0 && params.beta <= 1.0)) throw Error(ErrorCode::kUnprocessable, "beta must be in (0, 1]", "params.beta");
    const std::string mode = json::OptionalString(p, "dynamic_mode", 16, "params").value_or("exclude");
    if (mode == "exclude") params.dynamic_mode = engine::DynamicMode::kExcludeFromInput;
    else if (mode == "subtract") params.dynamic_mode = engine::DynamicMode::kSubtractFromMovable;
    else throw Error(ErrorCode::kInvalidArgument, "dynamic_mode must be exclude or subtract", "params.dynamic_mode");
    depth_scale = ParseDepthScale(json::FiniteNumberOr(p, "depth_scale", depth_scale, "params"), "params.depth_scale");
    strategy = json::OptionalString(p, "merge_strategy", 32, "params").value_or(strategy);
    if (strategy != "algorithm2" && strategy != "naive" && strategy != "naive_without_icp") {
      throw Error(ErrorCode::kInvalidArgument, "merge_strategy must be algorithm2, naive or naive_without_icp",
                  "params.merge_strategy");
    }
  }
  const bool merge = json::BoolOr(body, "merge", true);
  const std::int64_t stamp = body.contains("stamp") ? json::AsStampNs(body["stamp"], "stamp") : NowNs();

  auto model = std::make_shared<Model>();
  model->K = K;
  model->params = params;
  model->depth_scale = depth_scale;
  model->state = engine::NewSceneModel(K.width, K.height);
  storage::SceneRecord& r = model->record;
  r.map_id = map;
  r.intrinsics_json = IntrinsicsJson(K).dump();
  r.pose_json = json::ToJson(pose).dump();
  r.x_m = pose.position_m.x();
  r.y_m = pose.position_m.y();
  r.z_m = pose.position_m.z();
  r.params_json = Json{{"beta", params.beta},
                       {"dynamic_mode", params.dynamic_mode == engine::DynamicMode::kExcludeFromInput ? "exclude" : "subtract"},
                       {"depth_scale", depth_scale}}.dump();
  Json report = {{"requested", merge}, {"strategy", strategy}, {"performed", false}, {"candidates", Json::array()}};
  if (merge) {
    report["candidates"] = SelectCandidates(map, K, pose, stamp);
    report["pending"] = !report["candidates"].empty();  // the merge runs with the first frame (ICP needs it)
  }
  r.merge_report_json = report.dump();
  r.started_ns = stamp;
  r.id = store_.Write([&](storage::Connection& c) {
    if (!storage::FindMap(c, map)) throw Error(ErrorCode::kNotFound, "map '" + map + "' does not exist", "map");
    return storage::InsertScene(c, r);
  });
  {
    std::lock_guard<std::mutex> lock(models_mutex_);
    models_[r.id] = model;
  }
  std::lock_guard<std::mutex> lock(model->mutex);
  return Describe(*model);
}

std::shared_ptr<SceneService::Model> SceneService::Acquire(const std::string& map, std::int64_t id) {
  {
    std::lock_guard<std::mutex> lock(models_mutex_);
    auto it = models_.find(id);
    if (it != models_.end()) {
      if (it->second->record.map_id != map) throw Error(ErrorCode::kNotFound, "scene " + std::to_string(id) + " is not in map '" + map + "'", "scene");
      return it->second;
    }
  }
  auto record = store_.Read([&](storage::Connection& c) {
    if (!storage::FindMap(c, map)) throw Error(ErrorCode::kNotFound, "map '" + map + "' does not exist", "map");
    return storage::FindScene(c, map, id, true);
  });
  if (!record) throw Error(ErrorCode::kNotFound, "scene " + std::to_string(id) + " does not exist in map '" + map + "'", "scene");
  auto model = std::make_shared<Model>();
  model->K = IntrinsicsFromJson(Json::parse(record->intrinsics_json));
  const Json params = Json::parse(record->params_json);
  model->params.beta = params.at("beta").get<double>();
  model->params.dynamic_mode = params.at("dynamic_mode") == "subtract" ? engine::DynamicMode::kSubtractFromMovable
                                                                        : engine::DynamicMode::kExcludeFromInput;
  model->depth_scale = params.at("depth_scale").get<double>();
  model->state = engine::NewSceneModel(model->K.width, model->K.height);
  const std::size_t n = static_cast<std::size_t>(model->K.width) * model->K.height;
  if (record->state_version > 0) {
    model->state.background_m = DecodeAs<float>(record->background, BlobElement::kF32, n);
    model->state.weight = DecodeAs<float>(record->weight, BlobElement::kF32, n);
    const auto labels = DecodeAs<std::uint8_t>(record->labels, BlobElement::kU8, 2 * n);
    model->state.movable.assign(labels.begin(), labels.begin() + n);
    model->state.dynamic.assign(labels.begin() + n, labels.end());
    model->state.frames = record->frames;
  }
  record->background.clear();
  record->weight.clear();
  record->labels.clear();
  model->record = std::move(*record);
  store_.Read([&](storage::Connection& c) {
    for (const auto& k : storage::ListKeyframes(c, map, id)) {
      model->has_begin_keyframe = model->has_begin_keyframe || k.kind == "begin";
      model->next_action_layer = std::max(model->next_action_layer, k.action_layer + 1);
    }
  });
  if (model->record.status != "observing") return model;  // finished models are read from the database each time
  std::lock_guard<std::mutex> lock(models_mutex_);
  auto [it, inserted] = models_.emplace(id, model);
  return it->second;  // another thread may have loaded it first: use that one
}

void SceneService::Persist(Model& m) {
  storage::SceneRecord r = m.record;
  const int w = m.K.width, h = m.K.height;
  r.background = EncodeF32(m.state.background_m, w, h);
  r.weight = EncodeF32(m.state.weight, w, h);
  std::vector<std::uint8_t> labels(m.state.movable);
  labels.insert(labels.end(), m.state.dynamic.begin(), m.state.dynamic.end());
  r.labels = storage::EncodeBlob(BlobElement::kU8, {2, static_cast<std::uint32_t>(h), static_cast<std::uint32_t>(w)},
                                 storage::AsBytes(labels), 1);
  r.frames = m.state.frames;
  r.state_version = m.record.state_version + 1;
  store_.Write([&](storage::Connection& c) { storage::UpdateSceneState(c, r, m.record.state_version); });
  m.record.state_version = r.state_version;
  m.record.frames = r.frames;
  m.unpersisted_frames = 0;
}

Json SceneService::StoreKeyframe(Model& m, const std::string& kind, std::int64_t stamp_ns) {
  if (m.last_depth_mm.empty()) {
    throw Error(ErrorCode::kConflict, "scene " + std::to_string(m.record.id) + " has received no frame since it was (re)loaded");
  }
  const std::vector<std::uint16_t> background_mm = ToMillimetres(m.state.background_m);
  storage::KeyframeRecord k;
  k.map_id = m.record.map_id;
  k.scene_id = m.record.id;
  k.kind = kind;
  k.stamp_ns = stamp_ns;
  k.width = m.K.width;
  k.height = m.K.height;
  k.action_layer = m.next_action_layer;
  const std::vector<std::uint32_t> shape = {static_cast<std::uint32_t>(m.K.height), static_cast<std::uint32_t>(m.K.width)};
  k.depth = storage::EncodeBlob(BlobElement::kU16, shape, storage::AsBytes(m.last_depth_mm), 3, storage::BlobFilter::kDeltaShuffle16);
  k.background = storage::EncodeBlob(BlobElement::kU16, shape, storage::AsBytes(background_mm), 3, storage::BlobFilter::kDeltaShuffle16);
  k.raw_bytes = static_cast<std::int64_t>(2 * 2 * m.last_depth_mm.size());
  k.stored_bytes = static_cast<std::int64_t>(k.depth.size() + k.background.size());
  const std::int64_t id = store_.Write([&](storage::Connection& c) { return storage::InsertKeyframe(c, k); });
  ++m.next_action_layer;
  m.movable_at_keyframe = m.last_counts.movable;
  m.reset_since_keyframe = 0;
  m.stable_frames = 0;
  Json out = {{"keyframe", id}, {"kind", kind}, {"action_layer", k.action_layer}};
  if (listener_) {
    KeyframeNotice n;
    n.map = m.record.map_id;
    n.scene_id = m.record.id;
    n.keyframe_id = id;
    n.kind = kind;
    n.stamp_ns = stamp_ns;
    n.action_layer = k.action_layer;
    n.K = m.K;
    n.beta = m.params.beta;
    const Json report = Json::parse(m.record.merge_report_json);
    n.X_MapCamera = engine::ToIsometry(json::AsPose3(report.contains("pose_corrected") ? report["pose_corrected"] : Json::parse(m.record.pose_json), "pose"));
    for (const Json& used : report.value("models_used", Json::array())) n.merged_scenes.push_back(used.at("scene").get<std::int64_t>());
    n.depth_mm = &m.last_depth_mm;
    n.background_mm = &background_mm;
    out["analysis"] = listener_->OnKeyframe(n);
  }
  return out;
}

Json SceneService::AddFrame(const std::string& map, std::int64_t id, const FrameInput& in) {
  auto model = Acquire(map, id);
  std::lock_guard<std::mutex> lock(model->mutex);
  Model& m = *model;
  if (m.record.status != "observing") {
    throw Error(ErrorCode::kConflict, "scene " + std::to_string(id) + " is " + m.record.status + "; open a new one", "scene");
  }
  engine::DepthImage depth = in.png ? engine::DecodeDepthPng(in.body, "depth")
                                    : engine::DecodeDepthRaw(in.body, m.K.width, m.K.height, "depth");
  if (depth.width != m.K.width || depth.height != m.K.height) {
    throw Error(ErrorCode::kUnprocessable,
                "depth is " + std::to_string(depth.width) + "x" + std::to_string(depth.height) + " but the model's camera is " +
                    std::to_string(m.K.width) + "x" + std::to_string(m.K.height), "depth");
  }
  std::vector<std::uint8_t> dynamic;
  if (in.dynamic_png) {
    const engine::MaskImage mask = engine::DecodeMaskPng(*in.dynamic_png, "dynamic");
    if (mask.width != m.K.width || mask.height != m.K.height) {
      throw Error(ErrorCode::kUnprocessable, "the dynamic mask's size differs from the model's camera", "dynamic");
    }
    dynamic = std::move(mask.pixels);
  }
  const double scale = in.depth_scale ? ParseDepthScale(*in.depth_scale, "depth_scale") : m.depth_scale;
  const std::int64_t stamp = in.stamp_ns.value_or(NowNs());
  if (Json::parse(m.record.merge_report_json).value("pending", false)) {
    MergeFirstFrame(m, depth.pixels, scale, dynamic);
  } else {
    m.last_counts = engine::ApplyFrame(m.state, depth.pixels, scale, dynamic, m.params);
  }
  m.last_depth_mm.resize(depth.pixels.size());
  for (std::size_t i = 0; i < depth.pixels.size(); ++i) {
    m.last_depth_mm[i] = static_cast<std::uint16_t>(std::min(65535.0, std::round(depth.pixels[i] * 1000.0 / scale)));
  }
  m.record.last_frame_ns = stamp;
  ++m.unpersisted_frames;
  Json out = {{"scene", id}, {"frames", m.state.frames}};
  if (!m.has_begin_keyframe) {
    Json k = StoreKeyframe(m, "begin", stamp);
    out["keyframe"] = k["keyframe"];
    if (k.contains("analysis")) out["analysis"] = k["analysis"];
    m.has_begin_keyframe = true;
  } else if (limits_.settle_frames > 0) {
    // A completed movement: the movable layer changed since the last keyframe, then settled (3.3.4).
    const auto movable = static_cast<std::int64_t>(m.last_counts.movable);
    m.reset_since_keyframe += static_cast<std::int64_t>(m.last_counts.reset);
    const bool changed = std::abs(movable - m.movable_at_keyframe) >= limits_.settle_min_change_px ||
                         m.reset_since_keyframe >= limits_.settle_min_change_px;
    const bool steady = m.previous_movable >= 0 && std::abs(movable - m.previous_movable) <= limits_.settle_tolerance_px &&
                        m.last_counts.dynamic == 0 && m.last_counts.reset <= static_cast<std::size_t>(limits_.settle_tolerance_px);
    m.stable_frames = steady ? m.stable_frames + 1 : 0;
    if (changed && m.stable_frames >= limits_.settle_frames) {
      Json k = StoreKeyframe(m, "settled", stamp);
      out["keyframe"] = k["keyframe"];
      if (k.contains("analysis")) out["analysis"] = k["analysis"];
    }
  }
  m.previous_movable = static_cast<std::int64_t>(m.last_counts.movable);
  if (m.unpersisted_frames >= limits_.persist_every_frames) Persist(m);
  const auto& c = m.last_counts;
  out["persisted_frames"] = m.record.frames;
  out["pixels"] = {{"supported", c.supported}, {"reset", c.reset}, {"movable", c.movable}, {"dynamic", c.dynamic},
                   {"no_depth", c.no_depth}};
  return out;
}

Json SceneService::Describe(const Model& m) const {
  std::size_t movable = 0, dynamic = 0, known = 0;
  for (std::size_t i = 0; i < m.state.movable.size(); ++i) {
    movable += m.state.movable[i];
    dynamic += m.state.dynamic[i];
    known += m.state.background_m[i] > 0.0f;
  }
  const storage::SceneRecord& r = m.record;
  Json out = {{"id", r.id},
              {"map", r.map_id},
              {"status", r.status},
              {"camera", Json::parse(r.intrinsics_json)},
              {"pose", Json::parse(r.pose_json)},
              {"params", Json::parse(r.params_json)},
              {"merge", Json::parse(r.merge_report_json)},
              {"started_ns", r.started_ns},
              {"ended_ns", r.ended_ns ? Json(*r.ended_ns) : Json(nullptr)},
              {"last_frame_ns", r.last_frame_ns ? Json(*r.last_frame_ns) : Json(nullptr)},
              {"superseded_by", r.superseded_by ? Json(*r.superseded_by) : Json(nullptr)},
              {"frames", m.state.frames},
              {"persisted_frames", r.frames},
              {"statistics", {{"movable_pixels", movable}, {"dynamic_pixels", dynamic}, {"known_background_pixels", known}}}};
  return out;
}

Json SceneService::Get(const std::string& map, std::int64_t id) {
  auto model = Acquire(map, id);
  std::lock_guard<std::mutex> lock(model->mutex);
  Json out = Describe(*model);
  out["keyframes"] = Json::array();
  for (const auto& k : store_.Read([&](storage::Connection& c) { return storage::ListKeyframes(c, map, id); })) {
    out["keyframes"].push_back({{"id", k.id}, {"kind", k.kind}, {"stamp_ns", k.stamp_ns}});
  }
  return out;
}

ExportedLayer SceneService::Layer(const std::string& map, std::int64_t id, const std::string& layer,
                                  const std::string& format, bool clean) {
  auto model = Acquire(map, id);
  std::lock_guard<std::mutex> lock(model->mutex);
  const Model& m = *model;
  const int w = m.K.width, h = m.K.height;
  ExportedLayer out;
  out.headers = {{"X-Image-Width", std::to_string(w)}, {"X-Image-Height", std::to_string(h)},
                 {"X-Scene-Frames", std::to_string(m.state.frames)}};
  if (format != "png" && format != "raw" && format != "json") {
    throw Error(ErrorCode::kInvalidArgument, "format must be png, raw or json", "format");
  }
  if (layer == "movable" || layer == "dynamic") {
    std::vector<std::uint8_t> mask = layer == "movable" ? m.state.movable : m.state.dynamic;
    if (clean && layer == "movable") mask = engine::CleanMovable(mask, w, h);
    if (format == "png") return {"image/png", engine::EncodeMaskPng(mask, w, h), out.headers};
    if (format == "raw") return {"application/octet-stream", std::string(storage::AsBytes(mask)), out.headers};
    std::size_t n = 0;
    for (auto v : mask) n += v;
    return {"application/json", Json{{"layer", layer}, {"cleaned", clean && layer == "movable"}, {"pixels", n},
                                     {"fraction", static_cast<double>(n) / mask.size()}}.dump(), out.headers};
  }
  if (clean) throw Error(ErrorCode::kInvalidArgument, "clean applies to the movable layer only", "clean");
  if (layer == "static") {
    if (format == "png") return {"image/png", engine::EncodeDepthPng(ToMillimetres(m.state.background_m), w, h), out.headers};
    if (format == "raw") {
      out.headers["X-Element"] = "f32-metres";
      return {"application/octet-stream", std::string(storage::AsBytes(m.state.background_m)), out.headers};
    }
    double sum = 0;
    std::size_t known = 0;
    for (float v : m.state.background_m) if (v > 0) sum += v, ++known;
    return {"application/json", Json{{"layer", layer}, {"known_pixels", known}, {"mean_depth_m", known ? sum / known : 0.0}}.dump(),
            out.headers};
  }
  if (layer == "reliability") {
    if (format == "raw") {
      out.headers["X-Element"] = "f32-weight";
      return {"application/octet-stream", std::string(storage::AsBytes(m.state.weight)), out.headers};
    }
    if (format == "png") {
      std::vector<std::uint8_t> grey(m.state.weight.size());
      for (std::size_t i = 0; i < grey.size(); ++i) grey[i] = static_cast<std::uint8_t>(std::min(255.0f, m.state.weight[i]));
      return {"image/png", engine::EncodeGreyPng(grey, w, h), out.headers};
    }
    float max_w = 0;
    double sum = 0;
    for (float v : m.state.weight) max_w = std::max(max_w, v), sum += v;
    return {"application/json", Json{{"layer", layer}, {"max_weight", max_w}, {"mean_weight", sum / m.state.weight.size()}}.dump(),
            out.headers};
  }
  throw Error(ErrorCode::kNotFound, "scene layers are static, movable, dynamic and reliability", "layer");
}

Json SceneService::Keyframe(const std::string& map, std::int64_t id) {
  auto model = Acquire(map, id);
  std::lock_guard<std::mutex> lock(model->mutex);
  if (model->record.status != "observing") throw Error(ErrorCode::kConflict, "scene " + std::to_string(id) + " is " + model->record.status, "scene");
  const std::int64_t stamp = model->record.last_frame_ns.value_or(NowNs());
  Json out = StoreKeyframe(*model, "manual", stamp);
  out["scene"] = id;
  return out;
}

Json SceneService::Close(const std::string& map, std::int64_t id) {
  auto model = Acquire(map, id);
  std::lock_guard<std::mutex> lock(model->mutex);
  Model& m = *model;
  if (m.record.status != "observing") throw Error(ErrorCode::kConflict, "scene " + std::to_string(id) + " is already " + m.record.status, "scene");
  Json out = {{"scene", id}};
  const std::int64_t end = m.record.last_frame_ns.value_or(NowNs());
  if (!m.last_depth_mm.empty()) {
    Json k = StoreKeyframe(m, "end", end);
    out["keyframe"] = k["keyframe"];
    if (k.contains("analysis")) out["analysis"] = k["analysis"];
  }
  Persist(m);
  store_.Write([&](storage::Connection& c) { storage::UpdateSceneStatus(c, id, "closed", end, std::nullopt); });
  m.record.status = "closed";
  m.record.ended_ns = end;
  {
    std::lock_guard<std::mutex> models_lock(models_mutex_);  // closed models are not kept in memory
    models_.erase(id);
  }
  out["status"] = "closed";
  out["frames"] = m.state.frames;
  return out;
}

Json SceneService::List(const std::string& map, const storage::SceneFilter& filter) {
  return store_.Read([&](storage::Connection& c) {
    if (!storage::FindMap(c, map)) throw Error(ErrorCode::kNotFound, "map '" + map + "' does not exist", "map");
    Json out = {{"scenes", Json::array()}};
    for (const auto& r : storage::ListScenes(c, map, filter)) {
      out["scenes"].push_back({{"id", r.id}, {"status", r.status}, {"pose", Json::parse(r.pose_json)},
                               {"camera", Json::parse(r.intrinsics_json)}, {"started_ns", r.started_ns},
                               {"ended_ns", r.ended_ns ? Json(*r.ended_ns) : Json(nullptr)},
                               {"persisted_frames", r.frames}});
    }
    return out;
  });
}

Json SceneService::GetKeyframe(const std::string& map, std::int64_t id) {
  return store_.Read([&](storage::Connection& c) {
    if (!storage::FindMap(c, map)) throw Error(ErrorCode::kNotFound, "map '" + map + "' does not exist", "map");
    const auto k = storage::FindKeyframe(c, map, id, false);
    if (!k) throw Error(ErrorCode::kNotFound, "keyframe " + std::to_string(id) + " does not exist in map '" + map + "'", "keyframe");
    return Json{{"id", k->id}, {"scene", k->scene_id}, {"kind", k->kind}, {"stamp_ns", k->stamp_ns},
                {"width", k->width}, {"height", k->height}, {"raw_bytes", k->raw_bytes}, {"stored_bytes", k->stored_bytes},
                {"compression_ratio", static_cast<double>(k->stored_bytes) / static_cast<double>(k->raw_bytes)},
                {"pinned", k->pinned}};
  });
}

ExportedLayer SceneService::KeyframeImage(const std::string& map, std::int64_t id, const std::string& which) {
  return store_.Read([&](storage::Connection& c) {
    if (!storage::FindMap(c, map)) throw Error(ErrorCode::kNotFound, "map '" + map + "' does not exist", "map");
    const auto k = storage::FindKeyframe(c, map, id, true);
    if (!k) throw Error(ErrorCode::kNotFound, "keyframe " + std::to_string(id) + " does not exist in map '" + map + "'", "keyframe");
    const std::size_t n = static_cast<std::size_t>(k->width) * k->height;
    const auto pixels = DecodeAs<std::uint16_t>(which == "depth" ? k->depth : k->background, BlobElement::kU16, n);
    return ExportedLayer{"image/png", engine::EncodeDepthPng(pixels, k->width, k->height), {}};
  });
}

Json SceneService::SelectCandidates(const std::string& map, const PinholeIntrinsics& K, const Pose3& pose,
                                    std::int64_t stamp_ns) {
  storage::SceneFilter filter;
  filter.near_m = pose.position_m;
  filter.radius_m = merge_.candidate_radius_m;
  filter.limit = 50;
  const auto records = store_.Read([&](storage::Connection& c) { return storage::ListScenes(c, map, filter); });
  const Eigen::Isometry3d X_MC = engine::ToIsometry(pose);
  Json out = Json::array();
  for (const auto& r : records) {
    if (static_cast<int>(out.size()) >= merge_.max_candidates) break;
    if (r.status == "observing" || r.frames == 0) continue;  // only finished observations with a persisted state
    if (static_cast<double>(stamp_ns - r.started_ns) > merge_.max_age_s * 1e9) continue;
    const auto full = store_.Read([&](storage::Connection& c) { return storage::FindScene(c, map, r.id, true); });
    if (!full || full->background.empty()) continue;
    const PinholeIntrinsics Kj = IntrinsicsFromJson(Json::parse(full->intrinsics_json));
    const auto background = DecodeAs<float>(full->background, BlobElement::kF32, static_cast<std::size_t>(Kj.width) * Kj.height);
    std::vector<float> sparse(background.size(), 0.0f);  // every 8th pixel in both directions probes the overlap
    for (int v = 0; v < Kj.height; v += 8) for (int u = 0; u < Kj.width; u += 8) sparse[v * Kj.width + u] = background[v * Kj.width + u];
    const Pose3 pj = json::AsPose3(Json::parse(full->pose_json), "pose");
    const double overlap = engine::FrustumOverlap(engine::BackProject(sparse, Kj, engine::ToIsometry(pj)), K, X_MC,
                                                  merge_.frustum_far_m);
    if (overlap < merge_.min_overlap) continue;
    out.push_back({{"scene", r.id}, {"overlap", overlap}});
  }
  return out;
}

void SceneService::MergeFirstFrame(Model& m, const std::vector<std::uint16_t>& depth, double scale,
                                   const std::vector<std::uint8_t>& dynamic) {
  Json report = Json::parse(m.record.merge_report_json);
  const Pose3 pose = json::AsPose3(Json::parse(m.record.pose_json), "pose");
  const Eigen::Isometry3d X_MC = engine::ToIsometry(pose);
  std::vector<engine::PriorModel> priors;
  std::vector<Pose3> prior_poses;
  for (const Json& c : report["candidates"]) {
    const std::int64_t id = c["scene"].get<std::int64_t>();
    const auto full = store_.Read([&](storage::Connection& conn) { return storage::FindScene(conn, m.record.map_id, id, true); });
    if (!full || full->background.empty()) continue;  // forgotten meanwhile
    engine::PriorModel prior;
    prior.id = id;
    prior.K = IntrinsicsFromJson(Json::parse(full->intrinsics_json));
    prior_poses.push_back(json::AsPose3(Json::parse(full->pose_json), "pose"));
    prior.X_MapCamera = engine::ToIsometry(prior_poses.back());
    prior.background_m = DecodeAs<float>(full->background, BlobElement::kF32, static_cast<std::size_t>(prior.K.width) * prior.K.height);
    priors.push_back(std::move(prior));
  }
  engine::MergeParams params;
  params.beta = m.params.beta;
  params.frustum_far_m = merge_.frustum_far_m;
  const std::string strategy = report.value("strategy", "algorithm2");
  params.strategy = strategy == "naive" ? engine::MergeStrategy::kNaive
                    : strategy == "naive_without_icp" ? engine::MergeStrategy::kNaiveWithoutIcp
                                                       : engine::MergeStrategy::kAlgorithm2;
  const engine::MergeResult result = engine::MergeAndApplyFirstFrame(
      m.state, depth, scale, dynamic.empty() ? std::span<const std::uint8_t>() : dynamic, m.params, m.K, X_MC, priors, params);
  Json used = Json::array();
  for (const auto& r : result.models) {
    const Eigen::AngleAxisd aa(r.icp.correction.linear());
    const Eigen::Vector3d t = r.icp.correction.translation();
    used.push_back({{"scene", r.id},
                    {"icp", {{"converged", r.icp.converged}, {"applied", r.icp_applied}, {"fitness_m2", r.icp.fitness_m2}, {"fitness_before_m2", r.icp.fitness_before_m2},
                             {"correction", {{"translation_m", {t.x(), t.y(), t.z()}}, {"rotation_rad", aa.angle()}}},
                             {"source_points", r.icp.source_points}, {"target_points", r.icp.target_points}}},
                    {"pixels", {{"rasterised", r.rasterised_pixels}, {"supported", r.supported},
                                {"replaced_farther", r.replaced_farther}, {"rear_projected", r.rear_projected},
                                {"filled_unknown", r.filled_unknown}, {"rejected_fov", r.rejected_fov},
                                {"rejected_occlusion", r.rejected_occlusion},
                                {"rejected_neighbourhood", r.rejected_neighbourhood}}}});
  }
  // The registration also localises this camera against the earlier models: the best applied ICP correction gives
  // the pose the segments of this model are placed with (X_MC_corrected = X_MC * correction^-1).
  const engine::MergeModelReport* best_icp = nullptr;
  for (const auto& r : result.models) {
    if (r.icp_applied && (!best_icp || r.icp.fitness_m2 < best_icp->icp.fitness_m2)) best_icp = &r;
  }
  if (best_icp) {
    const Eigen::Isometry3d corrected = X_MC * best_icp->icp.correction.inverse();
    const Eigen::Quaterniond q(corrected.linear());
    report["pose_corrected"] = {{"position", {corrected.translation().x(), corrected.translation().y(), corrected.translation().z()}},
                                {"orientation", {q.x(), q.y(), q.z(), q.w()}}};
    report["pose_corrected_by_scene"] = best_icp->id;
  }
  report["performed"] = true;
  report["pending"] = false;
  report["models_used"] = used;
  report["timing_ms"] = {{"icp", result.timing.icp_ms}, {"rasterise", result.timing.rasterise_ms},
                         {"merge", result.timing.merge_ms}};
  // Supersession (3.3.4): earlier models from (nearly) the same viewpoint are now represented by this one.
  Json superseded = Json::array();
  const Eigen::Vector3d view = pose.orientation * Eigen::Vector3d::UnitZ();
  for (std::size_t k = 0; k < priors.size(); ++k) {
    const double distance = (prior_poses[k].position_m - pose.position_m).norm();
    const double angle = std::acos(std::clamp((prior_poses[k].orientation * Eigen::Vector3d::UnitZ()).dot(view), -1.0, 1.0));
    if (distance <= merge_.supersede_distance_m && angle <= merge_.supersede_angle_rad) superseded.push_back(priors[k].id);
  }
  report["superseded"] = superseded;
  m.record.merge_report_json = report.dump();
  const std::int64_t id = m.record.id;
  store_.Write([&](storage::Connection& c) {
    for (const Json& old : superseded) storage::UpdateSceneStatus(c, old.get<std::int64_t>(), "superseded", std::nullopt, id);
  });
  m.last_counts = engine::FrameCounts{};
  for (std::size_t i = 0; i < m.state.movable.size(); ++i) {
    m.last_counts.movable += m.state.movable[i];
    m.last_counts.dynamic += m.state.dynamic[i];
  }
  Persist(m);  // the merge is persisted with the model at once
}

void SceneService::PersistAll() {
  std::vector<std::shared_ptr<Model>> models;
  {
    std::lock_guard<std::mutex> lock(models_mutex_);
    for (auto& [id, m] : models_) models.push_back(m);
  }
  for (auto& m : models) {
    std::lock_guard<std::mutex> lock(m->mutex);
    if (m->unpersisted_frames > 0) Persist(*m);
  }
}

}  // namespace anchordb::api
