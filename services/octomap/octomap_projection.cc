// The height-band projection of the map's tree into 2D occupancy layers (octomap_server's multilayer variant).
#include <cmath>
#include <set>

#include "schema/error.h"
#include "schema/ids.h"
#include "services/octomap/octomap_service.h"

namespace anchordb::services {

ProjectResult OctomapService::Project(const ProjectRequest& request) {
  if (!grid_) throw Error(ErrorCode::kInternal, "the octomap service has no grid service to store layers in");
  if (request.bands.empty() || request.bands.size() > 16) {
    throw Error(ErrorCode::kUnprocessable, "give 1 to 16 bands", "bands");
  }
  std::set<std::string> names;
  std::vector<std::string> band_layers;
  for (const engine::HeightBand& b : request.bands) {
    json::CheckId(b.layer, "bands/layer");
    if (!names.insert(b.layer).second) {
      throw Error(ErrorCode::kUnprocessable, "layer '" + b.layer + "' is named by two bands", "bands");
    }
    if (!std::isfinite(b.min_z_m) || !std::isfinite(b.max_z_m) || b.min_z_m >= b.max_z_m) {
      throw Error(ErrorCode::kUnprocessable, "band '" + b.layer + "' needs finite min_z_m < max_z_m", "bands");
    }
    band_layers.push_back(b.layer);
  }
  const OctomapInfo info = Get(request.map);
  ProjectResult result;
  std::optional<std::string> like = request.like;
  if (!like) like = grid_->FirstOccupancyLayer(request.map, band_layers);
  if (like) {
    result.geometry = grid_->OccupancyGeometry(request.map, *like);
    result.geometry_from = "layer " + *like;
  } else {
    if (!info.metadata.min_map || !info.metadata.max_map) {
      throw Error(ErrorCode::kUnprocessable, "the tree is empty and the map has no occupancy layer to follow", "like");
    }
    const double resolution = request.resolution_m.value_or(info.params.resolution_m);
    if (!std::isfinite(resolution) || resolution < 0.005 || resolution > 5) {
      throw Error(ErrorCode::kUnprocessable, "resolution_m must be in [0.005, 5] m", "resolution_m");
    }
    result.geometry = engine::GridCovering(*info.metadata.min_map, *info.metadata.max_map, resolution);
    result.geometry_from = "tree";
  }
  const GridGeometry& g = result.geometry;
  double min_z = request.bands[0].min_z_m, max_z = request.bands[0].max_z_m;
  for (const engine::HeightBand& b : request.bands) {
    min_z = std::min(min_z, b.min_z_m);
    max_z = std::max(max_z, b.max_z_m);
  }
  const engine::Box3 box{{g.origin_x_m, g.origin_y_m, min_z},
                         {g.origin_x_m + g.width_cells * g.resolution_m, g.origin_y_m + g.height_cells * g.resolution_m,
                          max_z}};
  const std::vector<engine::Voxel> voxels = KnownVoxels(request.map, box);
  const double p = info.params.occupancy_threshold;
  const auto occupied_log_odds = static_cast<float>(std::log(p / (1 - p)));
  std::vector<std::pair<std::string, std::vector<std::int8_t>>> layers;
  for (const engine::HeightBand& b : request.bands) {
    layers.emplace_back(b.layer, engine::ProjectBand(voxels, occupied_log_odds, g, b));
  }
  const std::vector<LayerInfo> stored = grid_->PutOccupancyCells(request.map, g, layers);
  for (std::size_t i = 0; i < stored.size(); ++i) {
    result.bands.push_back({stored[i], request.bands[i], engine::CountBand(layers[i].second)});
  }
  return result;
}

}  // namespace anchordb::services
