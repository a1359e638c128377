#pragma once
// Typed requests and results of GridService (grid_service.h). Positions are in the map frame M [m], angles [rad],
// stamps integer nanoseconds since the Unix epoch; map, layer and agent ids are checked by the caller
// (json::IsValidId) before they get here.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "engine/grid/attention.h"
#include "engine/grid/layer_values.h"
#include "engine/grid/observation.h"
#include "engine/grid/regions.h"
#include "engine/grid/viewpoints.h"
#include "schema/types.h"
#include "storage/layer_codec.h"
#include "storage/repositories.h"

namespace anchordb::services {

// An axis-aligned box in the map frame [m] (min_x, min_y, max_x, max_y), as the store filters by it.
using Bbox = storage::Bbox;

// ---------------------------------------------------------------- maps

struct CreateMapRequest {
  std::string id;
  std::string name;
};

struct MapInfo {
  std::string id;
  std::string name;
  std::int64_t created_ns = 0;
};

struct ListMapsRequest {
  std::string after_id;  // cursor: maps with a greater id, in id order ("" = from the start)
  int limit = 100;       // >= 1
};

struct MapPage {
  std::vector<MapInfo> maps;
  std::optional<std::string> next_cursor;  // the last id of this page when more maps follow
};

struct LayerSummary {
  std::string name;
  LayerKind kind = LayerKind::kOccupancy;
};

struct MapDetails {
  MapInfo map;
  std::vector<LayerSummary> layers;  // in name order
  std::size_t agents = 0;            // tracked persons in the map
};

// ---------------------------------------------------------------- layers

// A map_server map: YAML text and a PGM or PNG image (bytes as uploaded; not owned, valid during the call).
struct OccupancyImport {
  std::string map;
  std::string layer;
  std::string_view yaml_text;
  std::string_view image_bytes;
};

// A probability layer over an occupancy layer of the same map, all cells at p = 0.5.
struct ProbabilityLayerSpec {
  static constexpr LayerKind kKind = LayerKind::kProbability;
  std::string base;
  LogOddsParams log_odds;
};

// A logical operator over 2..16 layers of the same map and grid, each thresholded (engine/grid/fusion.h).
struct FusedLayerSpec {
  static constexpr LayerKind kKind = LayerKind::kFused;
  FuseOp op = FuseOp::kAnd;
  std::vector<FuseOperand> operands;
};

// A label layer over an occupancy layer of the same map, no cell labelled; `labels` names ids 1..65535 up front.
struct LabelLayerSpec {
  static constexpr LayerKind kKind = LayerKind::kLabel;
  std::string base;
  std::map<int, std::string> labels;
};

using LayerSpec = std::variant<ProbabilityLayerSpec, FusedLayerSpec, LabelLayerSpec>;

struct CreateLayerRequest {
  std::string map;
  std::string layer;
  LayerSpec spec;
};

// What each kind keeps besides its cells (storage/layer_codec.h); the alternative matches LayerInfo::kind.
using LayerMeta = std::variant<storage::OccupancyLayerMeta, storage::ProbabilityLayerMeta, storage::FusedLayerMeta,
                               storage::LabelLayerMeta>;
// Occupancy layers count cells per class, label layers cells per label, the others summarise probabilities.
using LayerStatistics =
    std::variant<engine::OccupancyStatistics, engine::ProbabilityStatistics, engine::LabelStatistics>;

struct LayerInfo {
  std::string map;
  std::string name;
  LayerKind kind = LayerKind::kOccupancy;
  std::int64_t version = 1;  // +1 on every change of the cells
  std::int64_t created_ns = 0;
  std::int64_t updated_ns = 0;
  std::int64_t stored_bytes = 0;  // blob size in the database
  LayerMeta meta;
  std::optional<LayerStatistics> statistics;  // when asked for
};

// Formats a layer is exported in (the JSON description is GetLayer).
enum class LayerFormat { kPng, kPgm, kYaml, kRaw };

struct ObserveRequest {
  std::string map;
  std::string layer;  // a probability layer
  engine::Observation observation;
};

struct ObservationResult {
  std::string layer;
  std::int64_t version = 0;  // the layer's version after the update
  engine::ObservationCounts counts;
};

struct PaintLabelRequest {
  std::string map;
  std::string layer;  // a label layer
  std::string label;  // name; a new name gets the next free id
  std::vector<Polygon2> polygons_map;
};

struct PaintLabelResult {
  std::string layer;
  std::int64_t version = 0;
  std::string label;
  int label_id = 0;
  std::size_t cells = 0;  // cells inside the polygons
};

struct RegionsRequest {
  std::string map;
  std::string layer;
  double threshold = 0.5;  // probability a cell must exceed, [0, 1]
  double min_area_m2 = 0.0;
};

struct LayerRegions {
  std::string layer;
  std::int64_t version = 0;
  double threshold = 0.5;
  std::vector<engine::Region> regions;  // largest first
};

// ---------------------------------------------------------------- agents, attention, viewpoints

struct PutAgentRequest {
  std::string map;
  Agent agent;                            // agent.stamp_ns is replaced by `stamp_ns`
  std::optional<std::int64_t> stamp_ns;   // absent: the service clock's now
};

struct AttentionRequest {
  std::string map;
  std::string agent;
  std::string layer;       // any kind, read as probabilities
  double threshold = 0.5;  // regions are the cells above it
};

struct AttentionResult {
  std::string agent;
  std::string layer;
  engine::AttentionResult attention;
  std::optional<engine::Region> region;  // the attended region
};

struct ViewpointsRequest {
  std::string map;
  Eigen::Vector2d robot_m = Eigen::Vector2d::Zero();  // where the robot stands, p_map
  std::string agent;
  std::string layer;
  double threshold = 0.5;
  std::optional<int> region;  // region id of the layer; absent: the attended, else the nearest region
  int max_viewpoints = 10;
};

struct ViewpointsResult {
  std::string agent;
  std::string layer;
  engine::Region region;  // the surface the viewpoints look at
  engine::ViewpointPlan plan;
};

}  // namespace anchordb::services
