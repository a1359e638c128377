#pragma once
// The grid capability (maps, layers, observations, regions, agents, attention, viewpoints): typed requests in,
// typed results out (grid_types.h). It loads and stores through storage/, computes through engine/, and never
// sees HTTP or JSON (api/grid_routes.cc parses, calls one of these, serialises). Layer kinds are handled through
// one table (layer_kinds.h). Errors are anchordb::Error: kNotFound naming the map, layer, agent or region (field
// "map", "layer", "agent", "region"), kConflict for an existing id, a changed version or a layer others depend on,
// kUnprocessable for a request that cannot apply to the stored layers (a base that is not an occupancy layer,
// operands over different grids, an observation of a non-probability layer or from outside its grid).
#include <optional>
#include <string>
#include <vector>

#include "engine/grid/attention.h"
#include "engine/grid/viewpoints.h"
#include "schema/clock.h"
#include "services/common/exported_bytes.h"
#include "services/grid/grid_types.h"
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
  // `clock` stamps maps, layers and agents without a stamp; it must outlive the service.
  GridService(storage::Store& store, ServiceLimits limits, GridDefaults defaults,
              const Clock& clock = SystemClock::Instance());

  // ---- maps
  MapInfo CreateMap(const CreateMapRequest& request);
  MapPage ListMaps(const ListMapsRequest& request);
  MapDetails GetMap(const std::string& map);
  void DeleteMap(const std::string& map);  // with everything in it

  // ---- layers
  // Decodes and checks the YAML and image (kInvalidArgument, kPayloadTooLarge beyond max_map_pixels) before
  // touching the database.
  LayerInfo ImportOccupancyLayer(const OccupancyImport& request);
  LayerInfo CreateLayer(const CreateLayerRequest& request);
  std::vector<LayerInfo> ListLayers(const std::string& map);  // without statistics, in name order
  LayerInfo GetLayer(const std::string& map, const std::string& layer, bool with_statistics);
  // The bytes in `format`, with the grid's size, the layer's version (and the element type of raw).
  ExportedLayer ExportLayer(const std::string& map, const std::string& layer, LayerFormat format);
  void DeleteLayer(const std::string& map, const std::string& layer);  // kConflict while others depend on it
  ObservationResult Observe(const ObserveRequest& request);
  PaintLabelResult PaintLabel(const PaintLabelRequest& request);
  LayerRegions Regions(const RegionsRequest& request);

  // ---- agents, attention, viewpoints
  Agent PutAgent(const PutAgentRequest& request);  // create or replace; returns what is stored
  Agent GetAgent(const std::string& map, const std::string& agent);
  std::vector<Agent> ListAgents(const std::string& map, const std::optional<storage::Bbox>& bbox_map);
  AttentionResult Attention(const AttentionRequest& request);
  // kUnprocessable when the layer has no region above the threshold or the robot is not on known free space.
  ViewpointsResult Viewpoints(const ViewpointsRequest& request);

  // ---- occupancy layers written by another capability (the octomap's height-band projection)
  // The geometry of occupancy layer `layer` (kNotFound, or kUnprocessable field "like" for another kind).
  GridGeometry OccupancyGeometry(const std::string& map, const std::string& layer);
  // The first occupancy layer of the map in name order that is not in `except`, if any.
  std::optional<std::string> FirstOccupancyLayer(const std::string& map, const std::vector<std::string>& except);
  // Creates or replaces (next version) each named occupancy layer from cells (-1 unknown, 0 free, 100 occupied;
  // row-major, iy = 0 at the origin row) as a trinary map_server map (free 254, occupied 0, unknown 205), all in one
  // transaction. kConflict when a name is taken by a layer of another kind.
  std::vector<LayerInfo> PutOccupancyCells(const std::string& map, const GridGeometry& geometry,
                                           const std::vector<std::pair<std::string, std::vector<std::int8_t>>>& layers);

  const ServiceLimits& limits() const { return limits_; }

 private:
  storage::Store& store_;
  ServiceLimits limits_;
  GridDefaults defaults_;
  const Clock& clock_;
};

}  // namespace anchordb::services
