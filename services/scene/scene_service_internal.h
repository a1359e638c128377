#pragma once
// Internal to api/scene_service*.cc: the in-memory state of a scene model and the helpers its files share.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <mutex>

#include "services/scene/scene_service.h"
#include "engine/scene/scene_model.h"
#include "schema/error.h"
#include "storage/blob_codec.h"

namespace anchordb::services {

using storage::BlobElement;

namespace scene_detail {

inline std::int64_t NowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}

inline Json IntrinsicsJson(const PinholeIntrinsics& K) {
  return {{"width", K.width}, {"height", K.height}, {"fx", K.fx}, {"fy", K.fy}, {"cx", K.cx}, {"cy", K.cy}};
}

inline PinholeIntrinsics ParseIntrinsics(const Json& j, int max_side) {
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

inline PinholeIntrinsics IntrinsicsFromJson(const Json& j) {
  return {j.at("width").get<int>(), j.at("height").get<int>(), j.at("fx").get<double>(), j.at("fy").get<double>(),
          j.at("cx").get<double>(), j.at("cy").get<double>()};
}

inline double ParseDepthScale(double v, const std::string& field) {
  if (!(v > 0.0) || v > 1e6) throw Error(ErrorCode::kUnprocessable, "depth_scale must be in (0, 1e6] units per metre", field);
  return v;
}

inline std::string EncodeF32(const std::vector<float>& v, int w, int h) {
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

inline std::vector<std::uint16_t> ToMillimetres(const std::vector<float>& metres) {
  std::vector<std::uint16_t> mm(metres.size());
  for (std::size_t i = 0; i < metres.size(); ++i) {
    mm[i] = static_cast<std::uint16_t>(std::clamp(std::lround(metres[i] * 1000.0f), 0L, 65535L));
  }
  return mm;
}

}  // namespace scene_detail


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

}  // namespace anchordb::services
