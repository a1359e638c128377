#include "api/scene_json.h"
#include "api/request_limits.h"

#include <climits>
#include <cmath>

#include "schema/error.h"
#include "api/event_json.h"
#include "api/scene_documents_json.h"

namespace anchordb::api::scene_json {

using namespace anchordb::services;
namespace docs = api::scene_documents;

namespace {

PinholeIntrinsics ParseCamera(const Json& j) {
  if (!j.is_object()) throw Error(ErrorCode::kInvalidArgument, "camera must be an object {width,height,fx,fy,cx,cy}", "camera");
  json::RejectUnknownKeys(j, {"width", "height", "fx", "fy", "cx", "cy"}, "camera");
  const double w = json::RequireFiniteNumber(j, "width", "camera"), h = json::RequireFiniteNumber(j, "height", "camera");
  if (w != std::floor(w) || h != std::floor(h)) throw Error(ErrorCode::kInvalidArgument, "camera width/height must be integers", "camera.width");
  // Beyond the int range the value is clamped: the service refuses it with the range of its limits.
  const auto to_int = [](double v) { return static_cast<int>(std::clamp(v, double{INT_MIN}, double{INT_MAX})); };
  PinholeIntrinsics K;
  K.width = to_int(w);
  K.height = to_int(h);
  K.fx = json::RequireFiniteNumber(j, "fx", "camera");
  K.fy = json::RequireFiniteNumber(j, "fy", "camera");
  K.cx = json::RequireFiniteNumber(j, "cx", "camera");
  K.cy = json::RequireFiniteNumber(j, "cy", "camera");
  return K;
}

template <typename E>
E ParseChoice(const EnumNames<E>& names, const std::string& text, const std::string& message, const std::string& field) {
  const auto v = ValueOf(names, text);
  if (!v) throw Error(ErrorCode::kInvalidArgument, message, field);
  return *v;
}

void ParseParams(const Json& p, OpenSceneRequest& r) {
  if (!p.is_object()) throw Error(ErrorCode::kInvalidArgument, "params must be an object", "params");
  json::RejectUnknownKeys(p, {"beta", "dynamic_mode", "depth_scale", "merge_strategy"}, "params");
  r.params.model.beta = json::FiniteNumberOr(p, "beta", r.params.model.beta, "params");
  r.params.model.dynamic_mode = ParseChoice(kDynamicModeNames, json::OptionalString(p, "dynamic_mode", limits::kWordLength, "params").value_or("exclude"),
                                            "dynamic_mode must be exclude or subtract", "params.dynamic_mode");
  r.params.depth_scale = json::FiniteNumberOr(p, "depth_scale", r.params.depth_scale, "params");
  r.merge_strategy = ParseChoice(kMergeStrategyNames, json::OptionalString(p, "merge_strategy", limits::kWordLength, "params").value_or("algorithm2"),
                                 "merge_strategy must be algorithm2, naive or naive_without_icp", "params.merge_strategy");
}

Json OrNull(const std::optional<std::int64_t>& v) { return v ? Json(*v) : Json(nullptr); }

// "keyframe": id and "analysis" of a keyframe a request stored.
void AddKeyframe(Json& out, const std::optional<StoredKeyframe>& k) {
  if (!k) return;
  out["keyframe"] = k->id;
  if (k->analysis) out["analysis"] = KeyframeAnalysisStatusJson(*k->analysis);
}

}  // namespace

OpenSceneRequest ParseOpenScene(const Json& body) {
  json::RejectUnknownKeys(body, {"camera", "pose", "params", "merge", "stamp", "pose_sigma", "pose_covariance"});
  OpenSceneRequest r;
  if (body.contains("pose_sigma")) {
    const Json& s = body["pose_sigma"];
    if (!s.is_object()) {
      throw Error(ErrorCode::kInvalidArgument, "pose_sigma must be an object {translation_m, rotation_rad}", "pose_sigma");
    }
    json::RejectUnknownKeys(s, {"translation_m", "rotation_rad"}, "pose_sigma");
    r.pose_sigma = PoseSigma{json::RequireFiniteNumber(s, "translation_m", "pose_sigma"),
                             json::RequireFiniteNumber(s, "rotation_rad", "pose_sigma")};
  }
  if (body.contains("pose_covariance")) {
    const Json& c = body["pose_covariance"];
    if (!c.is_array() || c.size() > 36) {
      throw Error(ErrorCode::kInvalidArgument, "pose_covariance must be an array of 36 numbers (6x6, row-major)",
                  "pose_covariance");
    }
    std::vector<double> v;
    for (const Json& e : c) {
      if (!e.is_number()) throw Error(ErrorCode::kInvalidArgument, "pose_covariance must hold numbers only", "pose_covariance");
      v.push_back(e.get<double>());
    }
    r.pose_covariance = std::move(v);  // its length, symmetry and definiteness are the service's to check
  }
  r.camera = ParseCamera(json::Require(body, "camera"));
  r.X_MapCamera = json::AsPose3(json::Require(body, "pose"), "pose");
  if (body.contains("params")) ParseParams(body["params"], r);
  r.merge = json::BoolOr(body, "merge", true);
  if (body.contains("stamp")) r.stamp_ns = json::AsStampNs(body["stamp"], "stamp");
  return r;
}

Json SceneJson(const SceneInfo& s, bool with_keyframes) {
  const SceneInfo::State state = s.state.value_or(SceneInfo::State{});
  const SceneStatistics& st = state.statistics;
  Json out = {{"id", s.id},
              {"map", s.map},
              {"status", NameOf(kSceneStatusNames, s.status)},
              {"camera", docs::CameraDocument(s.camera)},
              {"pose", docs::PoseDocument(s.X_MapCamera)},
              {"pose_covariance", s.pose_covariance_map ? Json(std::vector<double>(s.pose_covariance_map->data(),
                                                                                   s.pose_covariance_map->data() + 36))
                                                        : Json(nullptr)},
              {"params", docs::ParamsDocument(s.params)},
              {"merge", docs::MergeReportDocument(s.merge)},
              {"started_ns", s.started_ns},
              {"ended_ns", OrNull(s.ended_ns)},
              {"last_frame_ns", OrNull(s.last_frame_ns)},
              {"superseded_by", OrNull(s.superseded_by)},
              {"frames", state.frames},
              {"persisted_frames", s.persisted_frames},
              {"statistics", {{"movable_pixels", st.movable_pixels}, {"dynamic_pixels", st.dynamic_pixels},
                              {"known_background_pixels", st.known_background_pixels}}}};
  if (with_keyframes) {
    out["keyframes"] = Json::array();
    for (const KeyframeRef& k : s.keyframes) {
      out["keyframes"].push_back({{"id", k.id}, {"kind", NameOf(kKeyframeKindNames, k.kind)}, {"stamp_ns", k.stamp_ns}});
    }
  }
  return out;
}

Json SceneListJson(const std::vector<SceneInfo>& scenes) {
  Json out = {{"scenes", Json::array()}};
  for (const SceneInfo& s : scenes) {
    out["scenes"].push_back({{"id", s.id}, {"status", NameOf(kSceneStatusNames, s.status)},
                             {"pose", docs::PoseDocument(s.X_MapCamera)}, {"camera", docs::CameraDocument(s.camera)},
                             {"started_ns", s.started_ns}, {"ended_ns", OrNull(s.ended_ns)},
                             {"persisted_frames", s.persisted_frames}});
  }
  return out;
}

Json FrameJson(const FrameResult& r) {
  const engine::FrameCounts& c = r.pixels;
  Json out = {{"scene", r.scene_id}, {"frames", r.frames}, {"persisted_frames", r.persisted_frames},
              {"pixels", {{"supported", c.supported}, {"reset", c.reset}, {"movable", c.movable}, {"dynamic", c.dynamic},
                          {"no_depth", c.no_depth}}}};
  AddKeyframe(out, r.keyframe);
  return out;
}

Json KeyframeJson(const KeyframeResult& r) {
  Json out = {{"scene", r.scene_id}, {"kind", NameOf(kKeyframeKindNames, r.keyframe.kind)},
              {"action_layer", r.keyframe.action_layer}};
  AddKeyframe(out, r.keyframe);
  return out;
}

Json CloseJson(const CloseResult& r) {
  Json out = {{"scene", r.scene_id}, {"status", NameOf(kSceneStatusNames, r.status)}, {"frames", r.frames}};
  AddKeyframe(out, r.keyframe);
  return out;
}

Json LayerSummaryJson(const SceneLayerSummary& s) {
  const char* layer = NameOf(kSceneLayerNames, s.kind);
  switch (s.kind) {
    case SceneLayerKind::kMovable:
    case SceneLayerKind::kDynamic:
      return {{"layer", layer}, {"cleaned", s.cleaned}, {"pixels", s.pixels}, {"fraction", s.fraction}};
    case SceneLayerKind::kStatic:
      return {{"layer", layer}, {"known_pixels", s.pixels}, {"mean_depth_m", s.mean_depth_m}};
    case SceneLayerKind::kReliability:
      break;
  }
  return {{"layer", layer}, {"max_weight", s.max_weight}, {"mean_weight", s.mean_weight}};
}

Json KeyframeInfoJson(const KeyframeInfo& k) {
  return {{"id", k.id}, {"scene", k.scene_id}, {"kind", NameOf(kKeyframeKindNames, k.kind)}, {"stamp_ns", k.stamp_ns},
          {"width", k.width}, {"height", k.height}, {"raw_bytes", k.raw_bytes}, {"stored_bytes", k.stored_bytes},
          {"compression_ratio", k.compression_ratio}, {"pinned", k.pinned}};
}

}  // namespace anchordb::api::scene_json
