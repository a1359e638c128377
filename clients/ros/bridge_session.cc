#include "clients/ros/bridge_session.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace anchordb::ros_bridge {

client::Pose ClientPose(const Eigen::Isometry3d& X) {
  client::Pose pose;
  const Eigen::Quaterniond q(X.linear());
  pose.position_m = {X.translation().x(), X.translation().y(), X.translation().z()};
  pose.orientation = {q.x(), q.y(), q.z(), q.w()};
  return pose;
}

SceneSession::SceneSession(client::Client& client, SessionSettings settings)
    : client_(client), settings_(std::move(settings)), rule_(settings_.rule) {}

template <typename Call>
bool SceneSession::Attempt(Call&& call, double now_s) {
  try {
    call();
    backoff_s_ = 0.0;
    return true;
  } catch (const client::TransportError& e) {
    last_error_ = std::string("no answer from the server: ") + e.what();
  } catch (const client::ApiError& e) {
    last_error_ = std::string("the server answered ") + std::to_string(e.status()) + ": " + e.what();
    if (e.status() < 500) {  // the request was refused, the server is fine
      if (e.status() == 404 || e.status() == 409) scene_.reset();  // the scene is gone or no longer observing
      return false;
    }
  }
  ++counts_.server_failures;
  backoff_s_ = backoff_s_ == 0.0 ? settings_.initial_backoff_s : std::min(2.0 * backoff_s_, settings_.max_backoff_s);
  retry_at_s_ = now_s + backoff_s_;
  return false;
}

void SceneSession::CloseScene() {
  if (!scene_) return;
  const std::int64_t id = *scene_;
  scene_.reset();
  try {
    client_.CloseScene(settings_.map, id);
    ++counts_.scenes_closed;
  } catch (const std::exception& e) {  // the scene stays observing on the server; it is not retried
    last_error_ = std::string("closing scene ") + std::to_string(id) + ": " + e.what();
    ++counts_.server_failures;
  }
}

FrameOutcome SceneSession::OnFrame(double stamp_s, const Eigen::Isometry3d& X_MapCamera, const client::Camera& camera,
                                   const std::vector<std::uint16_t>& depth_mm, const std::string& dynamic_png,
                                   double now_s) {
  ++counts_.offered;
  const engine::ObservationStep step = rule_.OnFrame(stamp_s, X_MapCamera);
  if (step.close_reason != engine::ObservationCloseReason::kNone || step.open) CloseScene();
  if (!step.feed) {
    ++counts_.skipped_moving;
    return FrameOutcome::kSkipped;
  }
  if (now_s < retry_at_s_) {
    ++counts_.dropped;
    return FrameOutcome::kDropped;
  }
  const auto stamp_ns = static_cast<std::int64_t>(std::llround(stamp_s * 1e9));
  if (!scene_ && !Attempt([&] {
        scene_ = client_.OpenScene(settings_.map, camera, ClientPose(X_MapCamera), settings_.merge, nullptr, stamp_ns).id;
        ++counts_.scenes_opened;
      }, now_s)) {
    ++counts_.dropped;
    return FrameOutcome::kDropped;
  }
  client::FrameResult answer;
  if (!Attempt([&] { answer = client_.PostDepthFrame(settings_.map, *scene_, depth_mm.data(), camera.width,
                                                     camera.height, stamp_ns, dynamic_png); }, now_s)) {
    ++counts_.dropped;
    return FrameOutcome::kDropped;
  }
  ++counts_.stored;
  if (!dynamic_png.empty()) ++counts_.frames_masked;
  const client::Json pixels = answer.raw.value("pixels", client::Json::object());
  if (pixels.is_object() && pixels.contains("dynamic") && pixels["dynamic"].is_number_integer()) {
    counts_.dynamic_pixels += pixels["dynamic"].get<std::int64_t>();
  }
  return FrameOutcome::kStored;
}

void SceneSession::Finish() {
  rule_.Finish();
  CloseScene();
}

}  // namespace anchordb::ros_bridge
