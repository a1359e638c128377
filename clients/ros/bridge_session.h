#pragma once
// The bridge's decision part without ROS types (C++17): depth frames with their optical-frame pose in the map frame go
// through the observation rule (engine/observation), and the rule's open / feed / close become calls of the anchordb
// C++ client. A frame counts as stored only when the server acknowledged it (2xx). A server that does not answer or
// answers 5xx puts the session in back-off (initial_backoff_s doubling to max_backoff_s, wall clock); frames meanwhile
// are dropped and counted, never stored later. A model whose scene the server no longer knows (404 / 409) is reopened
// at the next fed frame's pose.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <anchordb/client.h>

#include "engine/observation/observation_rule.h"

namespace anchordb::ros_bridge {

struct SessionSettings {
  std::string map = "home";
  bool merge = true;                 // each new scene model merges earlier ones of its place
  double initial_backoff_s = 0.5;    // first wait after a failed request
  double max_backoff_s = 8.0;        // the wait doubles up to this
  engine::ObservationRuleParams rule;
};

struct SessionCounts {
  std::int64_t offered = 0;          // frames offered
  std::int64_t stored = 0;           // acknowledged by the server
  std::int64_t skipped_moving = 0;   // the rule fed no model (moving, dwelling, or a stamp that did not advance)
  std::int64_t dropped = 0;          // to be fed, but the server was down, in back-off or refused the frame
  std::int64_t scenes_opened = 0;    // acknowledged opens
  std::int64_t scenes_closed = 0;    // acknowledged closes
  std::int64_t server_failures = 0;  // requests without an answer or with a 5xx answer
  std::int64_t frames_masked = 0;    // stored frames sent with a person mask (their dynamic input)
  std::int64_t dynamic_pixels = 0;   // dynamic pixels of the stored frames, as the server counted them
};

enum class FrameOutcome { kStored, kSkipped, kDropped };

class SceneSession {
 public:
  SceneSession(client::Client& client, SessionSettings settings);

  // One depth frame: its stamp [s], X_MapCamera (optical frame), the camera, row-major uint16 millimetres, and the
  // PNG of its person mask (8-bit, nonzero: a person; empty: none), posted as the frame's dynamic input.
  // now_s: the wall clock [s] that the back-off is measured on.
  FrameOutcome OnFrame(double stamp_s, const Eigen::Isometry3d& X_MapCamera, const client::Camera& camera,
                       const std::vector<std::uint16_t>& depth_mm, const std::string& dynamic_png, double now_s);
  // Closes the open model (end of the stream or shutdown); a failure is counted, not thrown.
  void Finish();

  const SessionCounts& counts() const { return counts_; }
  const std::string& last_error() const { return last_error_; }
  std::optional<std::int64_t> open_scene() const { return scene_; }
  double backoff_s() const { return backoff_s_; }

 private:
  void CloseScene();
  // Runs one request; true on success. A transport error or 5xx starts / lengthens the back-off.
  template <typename Call>
  bool Attempt(Call&& call, double now_s);

  client::Client& client_;
  SessionSettings settings_;
  engine::ObservationRule rule_;
  SessionCounts counts_;
  std::optional<std::int64_t> scene_;  // the server's scene of the open model (none yet: opened at the next fed frame)
  double retry_at_s_ = 0.0;
  double backoff_s_ = 0.0;
  std::string last_error_;
};

client::Pose ClientPose(const Eigen::Isometry3d& X);

}  // namespace anchordb::ros_bridge
