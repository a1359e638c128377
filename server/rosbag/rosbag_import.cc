// `anchordb import rosbag`: a ROS 1 bag into a map through the scene, grid and octomap services.
#include "server/rosbag/rosbag_import.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <stdexcept>

#include "engine/grid/occupancy_grid_image.h"
#include "engine/image/png_codec.h"
#include "schema/error.h"
#include "schema/json_io.h"
#include "services/audit/audit_service.h"
#include "services/events/analysis_queue.h"
#include "services/events/event_service.h"
#include "services/grid/grid_service.h"
#include "services/octomap/octomap_service.h"
#include "services/scene/scene_service.h"

namespace anchordb::server {
namespace {

namespace fs = std::filesystem;

// A scene model the rule decided on: the frames (indices into BagScan::frames) it takes, the first one opening it.
struct PlannedModel {
  std::vector<std::size_t> frames;
};

std::vector<PlannedModel> PlanModels(const BagScan& scan, const engine::ObservationRuleParams& params,
                                     RosbagImportSummary& summary) {
  engine::ObservationRule rule(params);
  std::vector<PlannedModel> models;
  for (std::size_t i = 0; i < scan.frames.size(); ++i) {
    const engine::ObservationStep step = rule.OnFrame(scan.frames[i].stamp_s, scan.frames[i].X_MapCamera);
    if (step.open) models.emplace_back();
    if (step.feed) models.back().frames.push_back(i);
  }
  rule.Finish();
  summary.skipped_moving = rule.counts().moving;
  summary.skipped_stamp = rule.counts().ignored;
  return models;
}

Pose3 PoseOf(const Eigen::Isometry3d& X) {
  Pose3 pose;
  pose.position_m = X.translation();
  pose.orientation = Eigen::Quaterniond(X.linear()).normalized();
  return pose;
}

std::int64_t StampNs(double stamp_s) { return static_cast<std::int64_t>(std::llround(stamp_s * 1e9)); }

// The grid as a map_server pair (PNG, top row = largest y; YAML with trinary thresholds) for ImportOccupancyLayer, the
// conversion the bridge node uses too (engine/grid/occupancy_grid_image.h).
void ImportGrid(services::GridService& grid, const std::string& map, const std::string& layer, const BagGrid& g) {
  engine::PngImage image;
  image.width = g.width, image.height = g.height, image.channels = 1, image.bit_depth = 8;
  image.bytes = engine::OccupancyGridImage(g.cells, g.width, g.height);
  const std::string png = engine::EncodePngImage(image);
  const std::string yaml = engine::OccupancyGridYaml("grid.png", g.resolution_m, g.origin_x_m, g.origin_y_m, g.origin_yaw_rad);
  services::OccupancyImport request;  // views of png and yaml
  request.map = map, request.layer = layer, request.yaml_text = yaml, request.image_bytes = png;
  grid.ImportOccupancyLayer(request);
}

// The services an import writes through, over one store; the OctoMap follows the keyframes as they come. Every stored
// keyframe's change analysis is queued (durably, in its own transaction, as the server's scene service does) and the
// import runs the queue itself at the end (no worker threads), so the events are there when it returns; a queued
// analysis the import did not get to (a crash) is run by the next server start. No JobService: constructing one marks
// a running server's unfinished jobs failed.
struct ImportServices {
  static services::OctomapSettings FromKeyframes(services::OctomapSettings settings) {
    settings.from_keyframes = true;
    return settings;
  }
  static services::AnalysisQueueSettings InCaller(services::AnalysisQueueSettings settings) {
    settings.threads = 0;
    return settings;
  }
  explicit ImportServices(const Config& config)
      : store(StoreOptionsOf(config.server)),
        grid(store, config.capabilities.limits, config.capabilities.grid),
        scenes(store, config.capabilities.scene, config.capabilities.merge),
        events(store, nullptr, config.capabilities.events),
        analysis(store, events, InCaller(config.capabilities.analysis)),
        octomap(store, FromKeyframes(config.capabilities.octomap), SystemClock::Instance(), &grid) {
    scenes.SetKeyframeListener(&analysis);
  }
  storage::Store store;
  services::GridService grid;
  services::SceneService scenes;
  services::EventService events;
  services::AnalysisQueue analysis;
  services::OctomapService octomap;
};

// Runs the queued change analyses of the keyframes stored (in keyframe order, in this thread) and collects the events
// they wrote (ids after `after_event`).
void AnalyseKeyframes(ImportServices& s, const std::string& map, std::int64_t after_event, RosbagImportSummary& summary) {
  summary.analyses = s.analysis.Drain(true);
  const services::AnalysisQueueView left = s.analysis.View(map);
  summary.analyses_failed = left.failed + left.pending;
  services::EventQuery q;
  q.after_id = after_event;
  q.limit = 1000;
  for (;;) {
    const services::EventPage page = s.events.ListEvents(map, q);
    for (const services::EventView& e : page.events) {
      summary.events.push_back({e.id, e.type, e.detection, e.instance_id.value_or(0)});
      q.after_id = std::max(q.after_id, e.id);
    }
    if (!page.next_after) break;
  }
}

void RequireMap(services::GridService& grid, const std::string& map, const std::string& db) {
  try {
    grid.GetMap(map);
  } catch (const Error& e) {
    if (e.code() != ErrorCode::kNotFound) throw;
    throw std::invalid_argument("unknown map '" + map + "' in " + db + " (create it first: POST /v1/maps)");
  }
}

PinholeIntrinsics CameraOf(const BagCamera& c) {
  PinholeIntrinsics camera;
  camera.width = c.width, camera.height = c.height;
  camera.fx = c.fx, camera.fy = c.fy, camera.cx = c.cx, camera.cy = c.cy;
  return camera;
}

// Feeds the planned models their depth images (read again from the bag, in bag order) with a progress line.
void StoreFrames(ImportServices& s, const RosbagImportOptions& o, const BagScan& scan,
                 const std::vector<PlannedModel>& models, RosbagImportSummary& summary, std::ostream& out) {
  const PinholeIntrinsics camera = CameraOf(scan.camera);
  std::vector<std::int64_t> wanted;
  std::vector<std::pair<std::size_t, std::size_t>> owner;  // (model, position in the model) of each wanted image
  for (std::size_t m = 0; m < models.size(); ++m) {
    for (std::size_t k = 0; k < models[m].frames.size(); ++k) {
      wanted.push_back(scan.frames[models[m].frames[k]].index);
      owner.emplace_back(m, k);
    }
  }
  out << "importing " << o.bag << " into map " << o.map << ": " << scan.depth_messages << " depth images ("
      << scan.encoding << ", " << camera.width << " x " << camera.height << "), " << wanted.size() << " in "
      << models.size() << " scene models\n" << std::flush;
  const auto start = std::chrono::steady_clock::now();
  std::int64_t scene_id = 0;
  std::size_t done = 0;
  ReadDepthImages(o.bag, o.topics, wanted, [&](std::int64_t, const BagDepthPixels& pixels) {
    const auto [m, k] = owner[done];
    const BagDepthFrame& f = scan.frames[models[m].frames[k]];
    if (k == 0) {
      services::OpenSceneRequest open;
      open.camera = camera;
      open.X_MapCamera = PoseOf(f.X_MapCamera);
      open.params.depth_scale = 1000.0;
      open.merge = o.merge;
      open.stamp_ns = StampNs(f.stamp_s);
      scene_id = s.scenes.Open(o.map, open).id;
      summary.scenes.push_back(scene_id);
    }
    std::string mask_png;
    services::FrameInput frame;
    frame.body = pixels.depth_mm_le;
    frame.png = false;
    frame.stamp_ns = StampNs(f.stamp_s);
    if (!pixels.mask.empty()) {
      engine::PngImage mask;
      mask.width = camera.width, mask.height = camera.height, mask.channels = 1, mask.bit_depth = 8;
      mask.bytes = pixels.mask;
      mask_png = engine::EncodePngImage(mask);
      frame.dynamic_png = mask_png;
    }
    const services::FrameResult stored = s.scenes.AddFrame(o.map, scene_id, frame);
    if (stored.keyframe) ++summary.keyframes;
    if (!pixels.mask.empty()) ++summary.frames_masked;
    summary.dynamic_pixels += static_cast<std::int64_t>(stored.pixels.dynamic);
    ++summary.frames_used;
    if (k + 1 == models[m].frames.size()) {
      if (s.scenes.Close(o.map, scene_id).keyframe) ++summary.keyframes;
      s.octomap.Follow(o.map);
    }
    ++done;
    const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    char line[160];
    std::snprintf(line, sizeof(line), "\rframe %zu/%zu  stamp %.3f  scene %lld  %.1f frames/s", done, wanted.size(),
                  f.stamp_s, static_cast<long long>(scene_id), done / std::max(elapsed_s, 1e-9));
    out << line << std::flush;
  });
  out << "\n";
  s.scenes.PersistAll();
  s.octomap.CommitPending();
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

json::Json SummaryJson(const RosbagImportOptions& o, const RosbagImportSummary& summary) {
  json::Json events = json::Json::array();
  for (const RosbagImportEvent& e : summary.events) {
    events.push_back({{"id", e.id}, {"type", e.type}, {"detection", e.detection}, {"instance", e.instance}});
  }
  return {{"bag", fs::absolute(o.bag).lexically_normal().string()},
          {"map", o.map},
          {"frames_read", summary.frames_read},
          {"frames_used", summary.frames_used},
          {"skipped_every", summary.skipped_every},
          {"skipped_no_pose", summary.skipped_no_pose},
          {"skipped_moving", summary.skipped_moving},
          {"skipped_stamp", summary.skipped_stamp},
          {"scenes", summary.scenes},
          {"keyframes", summary.keyframes},
          {"frames_masked", summary.frames_masked},
          {"dynamic_pixels", summary.dynamic_pixels},
          {"analyses", summary.analyses},
          {"analyses_not_done", summary.analyses_failed},
          {"events", events},
          {"grid_imported", summary.grid_imported},
          {"seconds", summary.seconds}};
}

}  // namespace

RosbagImportSummary ImportRosbag(const Config& config, const RosbagImportOptions& o, std::ostream& out) {
  RosbagImportSummary summary;
  // Everything about the bag is checked before the first write (a bad bag leaves the database as it was).
  const BagScan scan = ScanBag(o.bag, o.topics);
  BagGrid bag_grid;
  if (scan.has_grid) bag_grid = ReadLastGrid(o.bag, o.topics.grid);
  summary.frames_read = scan.depth_messages;
  summary.skipped_every = scan.skipped_every;
  summary.skipped_no_pose = scan.skipped_no_pose;
  const std::vector<PlannedModel> models = PlanModels(scan, o.rule, summary);

  ImportServices s(config);
  RequireMap(s.grid, o.map, config.server.db);
  if (scan.has_grid) {
    ImportGrid(s.grid, o.map, o.grid_layer, bag_grid);
    summary.grid_imported = true;
  }
  const std::int64_t events_before = s.events.LatestEventId(o.map);
  StoreFrames(s, o, scan, models, summary, out);
  AnalyseKeyframes(s, o.map, events_before, summary);
  const json::Json report = SummaryJson(o, summary);
  services::AuditEntry entry;
  entry.actor = "cli", entry.action = "map.import_rosbag", entry.map = o.map, entry.after_json = report.dump();
  services::AuditService(s.store).Record(std::move(entry));
  out << "imported " << summary.frames_used << " of " << summary.frames_read << " depth images (skipped: "
      << summary.skipped_every << " by --every, " << summary.skipped_no_pose << " without a tf pose, "
      << summary.skipped_moving << " while moving, " << summary.skipped_stamp << " stamp not advancing) into "
      << summary.scenes.size() << " scene models, " << summary.keyframes << " keyframes, " << summary.events.size()
      << " change events\n" << report.dump() << "\n";
  return summary;
}

}  // namespace anchordb::server
