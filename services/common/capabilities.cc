#include "services/capabilities.h"

#include "engine/grounding/knowledge.h"
#include "engine/octomap/leaf_centres.h"
#include "schema/error.h"

#include <algorithm>
#include <cmath>

#include "services/events/event_settings.h"
#include "services/features/feature_settings.h"
#include "services/furniture/furniture_settings.h"
#include "services/grid/grid_settings.h"
#include "services/jobs/job_settings.h"
#include "services/octomap/octomap_settings.h"
#include "services/scene/scene_settings.h"
#include "services/segmentation/segmentation_settings.h"
#include "services/shapes/shape_settings.h"

namespace anchordb::services {

namespace {
std::vector<std::string> CategoryIds(const std::string& knowledge_json) {
  std::vector<std::string> ids;
  const engine::grounding::Knowledge knowledge = engine::grounding::LoadKnowledge(knowledge_json);
  for (const auto& c : knowledge.categories.all()) ids.push_back(c.id);
  return ids;
}
// The map's OctoMap as points at its resolution (engine/octomap/leaf_centres.h). Up to `max_points` (more:
// kPayloadTooLarge).
std::optional<OccupiedCloud> OccupiedCloudOf(OctomapService& octomap, const std::string& map, std::size_t max_points) {
  octomap.Follow(map);  // keyframes stored since the tree's last update (with octomap_from_keyframes)
  if (!octomap.HasTree(map)) return std::nullopt;
  OccupiedCloud out;
  out.resolution_m = octomap.Get(map).params.resolution_m;
  const engine::Box3 everywhere{Eigen::Vector3d::Constant(-1e9), Eigen::Vector3d::Constant(1e9)};
  const VoxelsResult voxels = octomap.OccupiedVoxels(map, everywhere, std::nullopt);
  out.truncated = voxels.truncated;
  out.points_m = engine::LeafCentres(voxels.voxels, out.resolution_m, max_points);
  return out;
}

}  // namespace

void BindCapabilitySettings(SettingsBinder& b, CapabilityOptions& o) {
  BindGridSettings(b, o.limits, o.grid);
  BindSceneSettings(b, o.scene, o.merge);
  BindEventSettings(b, o.events);
  BindAnalysisQueueSettings(b, o.analysis);
  BindFurnitureSettings(b, o.furniture);
  BindJobSettings(b, o.jobs);
  BindOctomapSettings(b, o.octomap);
  BindFeatureSettings(b, o.features);
  BindShapeSettings(b, o.shapes);
  BindSegmentationSettings(b, o.segmentation);
}

Capabilities::Capabilities(storage::Store& store, const CapabilityOptions& o, const Clock& clock)
    : grid(store, o.limits, o.grid, clock),
      scenes(store, o.scene, o.merge, clock),
      furniture(store, o.furniture, clock),
      events(store, &furniture, o.events, clock),
      analysis(store, events, o.analysis, clock),
      jobs(store, o.jobs, clock),
      audit(store, clock),
      octomap(store, o.octomap, clock, &grid),
      octomap_feed(octomap, analysis),
      features(store, jobs, o.features, clock),
      keyframe_features(features, &octomap_feed, o.features.extract_every_keyframe),
      classifiers(store, jobs, features, grid, clock),
      shapes(store, jobs, o.shapes, clock),
      segmentation(store, jobs, CategoryIds(furniture.knowledge_json()), clock, SegmentationLinks{
          [this](const std::string& name) { return shapes.Find(name); },
          [this] { return shapes.Newest(); },
          [this, max_points = o.segmentation.max_cloud_points](const std::string& map) {
            return OccupiedCloudOf(octomap, map, max_points);
          }}, o.segmentation) {
  // Stored keyframes go to feature extraction (by setting), then the OctoMap feed, then the analysis queue.
  scenes.SetKeyframeListener(&keyframe_features);
}

}  // namespace anchordb::services
