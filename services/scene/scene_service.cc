#include "services/scene/scene_service.h"

#include "services/scene/scene_service_internal.h"
#include "services/events/transitional_analysis_json.h"  // TRANSITIONAL
#include "engine/scene/depth_image.h"
#include "engine/scene/projection.h"

namespace anchordb::services {

using namespace scene_detail;

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
    out["analysis"] = TransitionalAnalysisJson(listener_->OnKeyframe(n));
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
  // The PNG header's size is checked before decoding: a few bytes may declare a huge image.
  const auto declared = in.png ? engine::PngSize(in.body) : std::nullopt;
  if (declared && (declared->first != m.K.width || declared->second != m.K.height)) {
    throw Error(ErrorCode::kUnprocessable,
                "depth is " + std::to_string(declared->first) + "x" + std::to_string(declared->second) +
                    " but the model's camera is " + std::to_string(m.K.width) + "x" + std::to_string(m.K.height), "depth");
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

}  // namespace anchordb::services
