#pragma once
// The application functions behind the grid routes: they load and store through storage/, compute through
// engine/, and return JSON documents or bytes. They never see an HTTP request (the handlers in routes_*.cc
// parse, call one of these, and serialise), so they are tested directly as well as over HTTP.
#include <atomic>
#include <map>
#include <optional>
#include <string>

#include "engine/grid/attention.h"
#include "engine/grid/observation.h"
#include "engine/grid/viewpoints.h"
#include "services/common/exported_bytes.h"
#include "services/common/transitional_json.h"
#include "storage/repositories.h"
#include "storage/store.h"

namespace anchordb::services {


struct ServiceLimits {
  std::size_t max_map_pixels = 25'000'000;   // decoded map image size
  std::size_t max_polygons = 256;            // per request
  std::size_t max_polygon_vertices = 4096;   // per polygon
  int max_list_limit = 1000;                 // page size cap
};

struct GridDefaults {
  engine::OccupancyThresholds occupancy;
  engine::AttentionOptions attention;
  engine::ViewpointOptions viewpoints;
};


class GridService {
 public:
  GridService(storage::Store& store, ServiceLimits limits, GridDefaults defaults);

  // maps
  Json CreateMap(const std::string& id, const std::string& name);
  Json ListMaps(const std::string& after_id, int limit);
  Json GetMap(const std::string& id);
  void DeleteMap(const std::string& id);

  // layers
  Json ImportOccupancyLayer(const std::string& map, const std::string& layer, std::string_view yaml_text,
                            std::string_view image_bytes);
  // {"kind":"probability","base":..,"log_odds":{..}} | {"kind":"fused","op":..,"operands":[..]} |
  // {"kind":"label","base":..,"labels":{"1":"kitchen"}}
  Json CreateLayer(const std::string& map, const std::string& layer, const Json& body);
  Json ListLayers(const std::string& map);
  Json LayerInfo(const std::string& map, const std::string& layer, bool with_statistics);
  // format: png | pgm | yaml | raw
  ExportedLayer ExportLayer(const std::string& map, const std::string& layer, const std::string& format);
  void DeleteLayer(const std::string& map, const std::string& layer);
  Json Observe(const std::string& map, const std::string& layer, const engine::Observation& observation);
  Json PaintLabel(const std::string& map, const std::string& layer, const std::string& label,
                  const std::vector<Polygon2>& polygons);
  Json Regions(const std::string& map, const std::string& layer, double threshold, double min_area_m2);

  // agents and attention
  Json PutAgent(const std::string& map, const Agent& agent);
  Json GetAgent(const std::string& map, const std::string& id);
  Json ListAgents(const std::string& map, const std::optional<storage::Bbox>& bbox);
  Json Attention(const std::string& map, const std::string& agent, const std::string& layer, double threshold);
  Json Viewpoints(const std::string& map, const Eigen::Vector2d& robot_m, const std::string& agent,
                  const std::string& layer, double threshold, std::optional<int> region_id, int max_viewpoints);

  const ServiceLimits& limits() const { return limits_; }

 private:

  storage::Store& store_;
  ServiceLimits limits_;
  GridDefaults defaults_;
};

}  // namespace anchordb::services
