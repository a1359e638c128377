#pragma once
// anchordb_client: typed C++ calls of the anchordb HTTP API (SPEC §5) for robot components, over cpp-httplib and
// nlohmann-json (as the server). Every call throws anchordb::client::ApiError with the server's {code, message,
// field} and the HTTP status when the server refuses it, and TransportError when no answer came. Units and frames
// as the API: metres, radians, nanoseconds since the epoch; poses of the camera optical frame in the map frame
// (ROS order [qx, qy, qz, qw]); depth in millimetres (uint16, 0 = no measurement).
//
//   anchordb::client::Client c("127.0.0.1", 8765, token);
//   auto scene = c.OpenScene("home", camera, pose);
//   c.PostDepthFrame("home", scene.id, depth_mm.data(), camera.width, camera.height);
//   c.CloseScene("home", scene.id);
//   std::cout << c.Where("home", "keys").sentence;
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace anchordb::client {

using Json = nlohmann::json;

// The server refused a request: {"error":{"code","message","field"}} and the status.
class ApiError : public std::runtime_error {
 public:
  ApiError(int status, std::string code, std::string message, std::string field)
      : std::runtime_error(code + ": " + message + (field.empty() ? "" : " (" + field + ")")),
        status_(status), code_(std::move(code)), message_(std::move(message)), field_(std::move(field)) {}
  int status() const { return status_; }
  const std::string& code() const { return code_; }
  const std::string& message() const { return message_; }
  const std::string& field() const { return field_; }  // empty when the error names none

 private:
  int status_;
  std::string code_, message_, field_;
};

// No answer: the connection failed or timed out.
class TransportError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Pose {
  std::array<double, 3> position_m{0, 0, 0};
  std::array<double, 4> orientation{0, 0, 0, 1};  // qx, qy, qz, qw
};

struct Camera {  // pinhole intrinsics, as ROS CameraInfo K
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
};

struct MapInfo {
  std::string id, name;
  std::int64_t created_ns = 0;
};

struct Scene {
  std::int64_t id = 0;
  Json merge;  // the merge report (null when nothing was merged)
  Json raw;    // the whole answer
};

struct FrameResult {
  std::int64_t frames = 0;                // frames of the scene so far
  std::optional<std::int64_t> keyframe;   // a keyframe this frame stored
  Json raw;
};

struct Event {
  std::int64_t id = 0;
  std::string type, detection;  // added|removed|moved|labelled; observed|meanwhile|reanalysis|dialog|operator
  std::int64_t stamp_ns = 0;
  std::optional<std::int64_t> instance;
  std::optional<std::string> label;
  std::string explanation;
  Json raw;
};

struct EventQuery {
  std::optional<std::int64_t> since_ns, until_ns, instance;
  std::optional<std::string> type;
  std::int64_t after = 0;
  int limit = 100;
};

struct Instance {
  std::int64_t id = 0;
  std::string kind, status;
  Json labels;  // {label: probability}
  bool label_locked = false, pinned = false;
  std::array<double, 3> position_m{0, 0, 0};
  std::int64_t last_seen_ns = 0;
  Json raw;
};

struct WhereAnswer {
  bool present = false;
  std::optional<std::int64_t> instance;
  std::array<double, 3> position_m{0, 0, 0};
  std::string sentence;
  std::vector<std::int64_t> evidence_keyframes;
  Json raw;
};

struct Job {
  std::int64_t id = 0;
  std::string kind, status, stage;  // status queued|running|succeeded|failed
  double progress = 0.0;            // [0, 1]
  Json request, result;
  std::optional<std::string> error;
  bool finished() const { return status == "succeeded" || status == "failed"; }
};

class Client {
 public:
  // token: a Bearer token (empty for an open loopback server). timeout_s bounds each request's reads and writes.
  Client(std::string host, int port, std::string token = "", double timeout_s = 60.0);
  ~Client();
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;

  // Any route: JSON in (null: no body), JSON out.
  Json Request(const std::string& method, const std::string& path, const Json& body = nullptr);

  // Maps.
  MapInfo CreateMap(const std::string& id, const std::string& name = "");
  std::vector<MapInfo> ListMaps();
  MapInfo GetMap(const std::string& id);
  void DeleteMap(const std::string& id);  // admin

  // Layers: a ROS map_server import (YAML text + PGM or PNG bytes) and exports (format png|pgm|yaml|raw|json).
  Json ImportLayer(const std::string& map, const std::string& layer, const std::string& yaml_text,
                   const std::string& image_bytes);
  Json CreateLayer(const std::string& map, const std::string& layer, const Json& spec);
  std::string ExportLayer(const std::string& map, const std::string& layer, const std::string& format);
  Json ListLayers(const std::string& map);

  // Scene models: open with camera and pose, frames from a uint16 millimetre buffer (row-major, width*height) with
  // optionally an 8-bit PNG of the frame's dynamic pixels (nonzero: a person; the frame's dynamic input, sent as the
  // multipart part "dynamic"), close (the end keyframe; wait_for_analysis: the answer carries its change analysis).
  // stamp_ns: when the observation began (the first frame's sensor stamp); none: the server's clock.
  Scene OpenScene(const std::string& map, const Camera& camera, const Pose& pose, bool merge = true,
                  const Json& params = nullptr, std::optional<std::int64_t> stamp_ns = std::nullopt);
  FrameResult PostDepthFrame(const std::string& map, std::int64_t scene, const std::uint16_t* depth_mm, int width,
                             int height, std::optional<std::int64_t> stamp_ns = std::nullopt,
                             const std::string& dynamic_png = "");
  Json CloseScene(const std::string& map, std::int64_t scene, bool wait_for_analysis = false);
  Json GetScene(const std::string& map, std::int64_t scene);

  // Events, instances, where-is.
  std::vector<Event> Events(const std::string& map, const EventQuery& query = {});
  std::vector<Instance> Instances(const std::string& map, const std::string& label = "", const std::string& kind = "");
  Instance GetInstance(const std::string& map, std::int64_t id);
  Json LabelInstance(const std::string& map, std::int64_t id, const std::string& label, bool from_operator = false);
  WhereAnswer Where(const std::string& map, const std::string& label);

  // Furniture graphs: create ({viewpoint, furniture, params}), ground a description (text), the n-best, speak.
  Json CreateFurnitureGraph(const std::string& map, const Json& body);
  Json GroundDescription(const std::string& map, std::int64_t graph, const std::string& text);
  Json Hypotheses(const std::string& map, std::int64_t graph, int limit = 10);
  Json Describe(const std::string& map, std::int64_t graph, const std::string& located, const std::string& reference);

  // Jobs: forgetting (admin), backups (admin), progress, and waiting with a progress callback.
  Job Forget(const std::string& map, const Json& policy, bool dry_run);
  Job Backup(const std::string& label = "");
  Job GetJob(std::int64_t id);
  // Polls every poll_s until the job finished; on_progress sees each state; TransportError after timeout_s.
  Job WaitJob(std::int64_t id, const std::function<void(const Job&)>& on_progress = {}, double timeout_s = 600.0,
              double poll_s = 0.2);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace anchordb::client
