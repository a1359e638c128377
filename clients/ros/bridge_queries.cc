// anchordb_ros: what the memory learns, back to ROS (bridge_node.h): the map made sure of, events, instance markers,
// status, and the where_is / label services. Every server failure is logged (throttled, on /rosout), never thrown.
#include <cmath>
#include <cstring>
#include <string>

#include <anchordb_ros/ChangeEvent.h>
#include <std_msgs/String.h>
#include <visualization_msgs/MarkerArray.h>

#include "clients/ros/bridge_node.h"

namespace anchordb::ros_bridge {
namespace {

ros::Time TimeOfNs(std::int64_t ns) {
  ros::Time t;
  t.fromNSec(static_cast<std::uint64_t>(std::max<std::int64_t>(ns, 0)));
  return t;
}

// The most likely label of an instance ({label: probability}); empty when it has none.
std::string TopLabel(const client::Json& labels) {
  std::string best;
  double p = -1.0;
  if (!labels.is_object()) return best;
  for (auto it = labels.begin(); it != labels.end(); ++it) {
    if (it.value().is_number() && it.value().get<double>() > p) best = it.key(), p = it.value().get<double>();
  }
  return best;
}

}  // namespace

bool BridgeNode::EnsureMap() {
  try {
    query_client_.GetMap(p_.map);
    map_ready_ = true;
  } catch (const client::ApiError& e) {
    if (e.status() != 404 || !p_.create_map) {
      ROS_WARN_THROTTLE(5.0, "anchordb_ros: map '%s': %s", p_.map.c_str(), e.what());
      return false;
    }
    try {
      query_client_.CreateMap(p_.map);
      map_ready_ = true;
      ROS_INFO("anchordb_ros: created map '%s'", p_.map.c_str());
    } catch (const std::exception& c) {
      ROS_WARN_THROTTLE(5.0, "anchordb_ros: creating map '%s': %s", p_.map.c_str(), c.what());
    }
  } catch (const std::exception& e) {
    ROS_WARN_THROTTLE(5.0, "anchordb_ros: server unreachable (%s); retrying", e.what());
  }
  return map_ready_;
}

void BridgeNode::Poll(const ros::TimerEvent&) {
  DrainPending(false);  // depth images whose mask did not come in time
  ImportGrid();         // a map received while the server was away
  PublishStatus();
  if (!map_ready_ && !EnsureMap()) return;
  try {
    PublishEvents();
    PublishMarkers();
    PublishLayers();
  } catch (const std::exception& e) {
    ROS_WARN_THROTTLE(5.0, "anchordb_ros: polling the server: %s", e.what());
  }
}

// Where ~events starts: after the map's newest event (or at its first with ~publish_past_events). The constructor
// tries it, so that an event made once the services are up (a ~label call) is never taken for a past one; with the
// server away at start, the first poll that reaches it does.
void BridgeNode::PrimeEvents() {
  if (!p_.publish_past_events) {
    for (;;) {
      client::EventQuery q;
      q.after = last_event_;
      q.limit = 1000;
      const std::vector<client::Event> events = query_client_.Events(p_.map, q);
      for (const client::Event& e : events) last_event_ = std::max(last_event_, e.id);
      if (events.size() < 1000) break;
    }
  }
  events_primed_ = true;
}

void BridgeNode::PublishEvents() {
  if (!events_primed_) return PrimeEvents();
  for (;;) {
    client::EventQuery q;
    q.after = last_event_;
    q.limit = 100;
    const std::vector<client::Event> events = query_client_.Events(p_.map, q);
    for (const client::Event& e : events) {
      last_event_ = std::max(last_event_, e.id);
      anchordb_ros::ChangeEvent m;
      m.id = e.id, m.type = e.type, m.detection = e.detection, m.instance = e.instance.value_or(0);
      m.label = e.label.value_or(""), m.stamp = TimeOfNs(e.stamp_ns), m.explanation = e.explanation;
      if (e.instance) {  // the event names the instance; its position is the instance's
        const client::Instance i = query_client_.GetInstance(p_.map, *e.instance);
        m.position.x = i.position_m[0], m.position.y = i.position_m[1], m.position.z = i.position_m[2];
      }
      for (const client::Json& k : e.raw.value("evidence", client::Json::array())) {
        if (k.is_object() && k.contains("keyframe") && k["keyframe"].is_number_integer()) {
          m.evidence_keyframes.push_back(k["keyframe"].get<std::int64_t>());
        }
      }
      events_pub_.publish(m);
    }
    if (events.size() < 100) break;
  }
}

void BridgeNode::PublishMarkers() {
  visualization_msgs::MarkerArray markers;
  visualization_msgs::Marker clear;
  clear.action = visualization_msgs::Marker::DELETEALL;
  markers.markers.push_back(clear);
  for (const client::Instance& i : query_client_.Instances(p_.map)) {
    if (i.status != "present") continue;
    visualization_msgs::Marker sphere;
    sphere.header.frame_id = p_.map_frame, sphere.header.stamp = ros::Time::now();
    sphere.ns = "instances", sphere.id = static_cast<int>(i.id), sphere.type = visualization_msgs::Marker::SPHERE;
    sphere.pose.position.x = i.position_m[0], sphere.pose.position.y = i.position_m[1];
    sphere.pose.position.z = i.position_m[2], sphere.pose.orientation.w = 1.0;
    sphere.scale.x = sphere.scale.y = sphere.scale.z = 0.1;
    sphere.color.r = 1.0f, sphere.color.g = 0.6f, sphere.color.a = 1.0f;
    markers.markers.push_back(sphere);
    visualization_msgs::Marker text = sphere;
    text.ns = "labels", text.type = visualization_msgs::Marker::TEXT_VIEW_FACING, text.text = TopLabel(i.labels);
    text.pose.position.z += 0.15;
    text.color.r = text.color.g = text.color.b = 1.0f;
    markers.markers.push_back(text);
  }
  markers_pub_.publish(markers);
}

// A probability layer's stored log-odds (raw export, f32 in cell order: row-major from the origin, as OccupancyGrid)
// as probabilities 0..100; published again only when the layer's version changed.
void BridgeNode::PublishLayers() {
  for (auto& [layer, publisher] : layer_pubs_) {
    const client::Json meta = query_client_.Request("GET", "/v1/maps/" + p_.map + "/layers/" + layer);
    if (meta.value("kind", "") != "probability") {
      ROS_WARN_THROTTLE(30.0, "anchordb_ros: layer '%s' is not a probability layer", layer.c_str());
      continue;
    }
    const std::int64_t version = meta.value("version", std::int64_t{0});
    if (layer_versions_.count(layer) && layer_versions_[layer] == version) continue;
    const client::Json& g = meta.at("geometry");
    nav_msgs::OccupancyGrid grid;
    grid.header.frame_id = p_.map_frame, grid.header.stamp = ros::Time::now();
    grid.info.resolution = g.at("resolution_m").get<float>();
    grid.info.width = g.at("width_cells").get<std::uint32_t>(), grid.info.height = g.at("height_cells").get<std::uint32_t>();
    const client::Json& origin = g.at("origin");  // x, y, yaw
    grid.info.origin.position.x = origin.at(0).get<double>(), grid.info.origin.position.y = origin.at(1).get<double>();
    const double yaw = origin.size() > 2 ? origin.at(2).get<double>() : 0.0;
    grid.info.origin.orientation.z = std::sin(yaw / 2), grid.info.origin.orientation.w = std::cos(yaw / 2);
    const std::string raw = query_client_.ExportLayer(p_.map, layer, "raw");
    const std::size_t cells = static_cast<std::size_t>(grid.info.width) * grid.info.height;
    if (raw.size() != cells * 4) {
      ROS_WARN_THROTTLE(30.0, "anchordb_ros: layer '%s': %zu raw bytes for %zu cells", layer.c_str(), raw.size(), cells);
      continue;
    }
    grid.data.resize(cells);
    for (std::size_t i = 0; i < cells; ++i) {
      float log_odds = 0;
      std::memcpy(&log_odds, raw.data() + 4 * i, 4);
      grid.data[i] = static_cast<std::int8_t>(std::lround(100.0 / (1.0 + std::exp(-static_cast<double>(log_odds)))));
    }
    publisher.publish(grid);
    layer_versions_[layer] = version;
  }
}

void BridgeNode::PublishStatus() {
  const SessionCounts& c = session_.counts();
  std_msgs::String m;
  m.data = client::Json{{"offered", c.offered}, {"stored", c.stored}, {"skipped", c.skipped_moving},
                        {"dropped", c.dropped}, {"no_tf", tf_drops_}, {"scenes_opened", c.scenes_opened},
                        {"scenes_closed", c.scenes_closed}, {"server_failures", c.server_failures},
                        {"masked", c.frames_masked}, {"dynamic_pixels", c.dynamic_pixels},
                        {"without_mask", without_mask_}, {"masks_refused", masks_refused_},
                        {"grid_imported", grid_done_}, {"last_error", session_.last_error()}}.dump();
  status_pub_.publish(m);
}

bool BridgeNode::WhereIs(anchordb_ros::WhereIs::Request& req, anchordb_ros::WhereIs::Response& res) {
  try {
    const client::WhereAnswer a = query_client_.Where(p_.map, req.label);
    res.found = a.present;
    res.pose.header.frame_id = p_.map_frame;
    res.pose.header.stamp = ros::Time::now();
    res.pose.pose.position.x = a.position_m[0], res.pose.pose.position.y = a.position_m[1];
    res.pose.pose.position.z = a.position_m[2], res.pose.pose.orientation.w = 1.0;
    if (a.raw.contains("seen_ns") && a.raw["seen_ns"].is_number_integer()) {
      res.last_seen = TimeOfNs(a.raw["seen_ns"].get<std::int64_t>());
    }
    res.sentence = a.sentence;
  } catch (const client::ApiError& e) {  // e.g. no instance with the label: an answer, not a failed call
    res.found = false;
    res.sentence = e.message();
  } catch (const std::exception& e) {
    ROS_WARN("anchordb_ros: where_is '%s': %s", req.label.c_str(), e.what());
    return false;
  }
  return true;
}

bool BridgeNode::Label(anchordb_ros::Label::Request& req, anchordb_ros::Label::Response& res) {
  try {
    query_client_.LabelInstance(p_.map, req.instance, req.label, req.from_operator);
    res.ok = true;
    res.message = "instance " + std::to_string(req.instance) + " is now '" + req.label + "'";
  } catch (const client::ApiError& e) {
    res.ok = false;
    res.message = e.message();
  } catch (const std::exception& e) {
    ROS_WARN("anchordb_ros: label: %s", e.what());
    return false;
  }
  return true;
}

}  // namespace anchordb::ros_bridge
