#pragma once
// Internal to services/grid: the table of layer kinds. Each kind (layer_kind_<name>.cc) says, in one LayerKindOps,
// how a layer of that kind is created from its spec, what metadata it shows, how it reads as per-cell
// probabilities, what statistics it reports, which export formats it renders itself and which occupancy layer it
// lies on. GridService never branches on a kind. A new kind (an OctoMap projection, a room-label layer) is a new
// file with its LayerKindOps and one line in layer_kinds.cc, besides the types it needs: its LayerKind value
// (schema/types.h, storage's LayerKindFromName), its record format (storage/layer_codec.h), its spec and metadata
// alternatives (grid_types.h) and their JSON (api/grid_json.cc).
#include <optional>
#include <string>
#include <vector>

#include "engine/grid/grid.h"
#include "engine/grid/map_server.h"
#include "services/common/exported_bytes.h"
#include "services/grid/grid_types.h"
#include "storage/layer_codec.h"
#include "storage/repositories.h"
#include "services/common/require.h"

namespace anchordb::services::grid_detail {

// Checks the map exists (kNotFound, field "map").
using services::RequireMap;

// The layers of one map, read inside a read or write transaction. Constructing it checks the map exists
// (kNotFound, field "map").
class MapLayers {
 public:
  // Checks that the map exists (kNotFound), unless `check_map` is false: then a missing map is found out (and
  // reported as such) only when a layer is not found, which saves a reader a statement.
  MapLayers(storage::Connection& c, const std::string& map, bool check_map = true);

  // A layer of the map (with its blob unless !with_data); kNotFound naming it (field "layer"), or the map when the
  // map does not exist.
  storage::LayerRecord Require(const std::string& layer, bool with_data = true) const;
  // An occupancy layer of the map a new or planned layer builds on (kUnprocessable otherwise, field "base").
  storage::LayerRecord RequireOccupancy(const std::string& base) const;
  // Any layer as per-cell probabilities, through its kind; layers reading others (fused) nest at most 8 deep
  // (kUnprocessable beyond).
  engine::ProbabilityGrid Probability(const storage::LayerRecord& record, int depth = 0) const;
  // The name of the occupancy layer `record` lies on, through its kind.
  std::string OccupancyBase(const storage::LayerRecord& record) const;

 private:
  storage::Connection& c_;
  std::string map_;
};

struct LayerKindOps {
  LayerKind kind = LayerKind::kOccupancy;
  // Fills kind, meta and data of the new layer `record` from `spec` (this kind's alternative), checking the
  // layers it builds on; returns the names of the layers it depends on. nullptr: layers of this kind are made
  // another way (occupancy layers are imported).
  std::vector<std::string> (*create)(const MapLayers& layers, const LayerSpec& spec, storage::LayerRecord& record) =
      nullptr;
  LayerMeta (*meta)(const storage::LayerRecord& record) = nullptr;
  engine::ProbabilityGrid (*probability)(const MapLayers& layers, const storage::LayerRecord& record, int depth) =
      nullptr;
  LayerStatistics (*statistics)(const MapLayers& layers, const storage::LayerRecord& record,
                                const engine::OccupancyThresholds& thresholds) = nullptr;
  // The kind's own rendering of `format` (body, content type, X-Element); nullopt: the layer is exported as its
  // probabilities (ExportProbability).
  std::optional<ExportedLayer> (*export_own)(const storage::LayerRecord& record, LayerFormat format) = nullptr;
  std::string (*occupancy_base)(const MapLayers& layers, const storage::LayerRecord& record) = nullptr;
};

// The entry of `kind`; kInternal when the table has none (a kind added without its entry).
const LayerKindOps& KindOps(LayerKind kind);
// Every entry, in table order.
const std::vector<const LayerKindOps*>& AllKinds();
LayerKind KindOf(const LayerSpec& spec);

// A record as the service describes it (no statistics).
LayerInfo DescribeLayer(const storage::LayerRecord& record);
// A probability grid as an image (png, pgm), its map_server YAML (scale mode, image "<layer>.pgm") or its true
// cells as a u8 mask (raw).
ExportedLayer ExportProbability(const engine::ProbabilityGrid& probability, const std::string& layer,
                                LayerFormat format);

// An occupancy layer decoded: the image as imported, its YAML values and map_server's reading of the pixels.
struct OccupancyView {
  engine::GreyImage image;
  MapServerMeta map_server;
  engine::OccupancyGrid grid;
};
OccupancyView DecodeOccupancyView(const storage::LayerRecord& record);

// Cells of a decoded record over its geometry.
template <typename T>
engine::Grid<T> GridOf(const GridGeometry& geometry, std::vector<T> cells) {
  engine::Grid<T> grid;
  grid.geometry = geometry;
  grid.cells = std::move(cells);
  return grid;
}

// The kinds' entries (layer_kind_<name>.cc).
extern const LayerKindOps kOccupancyKind;
extern const LayerKindOps kProbabilityKind;
extern const LayerKindOps kFusedKind;
extern const LayerKindOps kLabelKind;

}  // namespace anchordb::services::grid_detail
