#pragma once
// Every capability of the memory composed on one store: the options of each (defaults in their structs, settings
// bound in services/<capability>/*_settings.cc) and the services built from them, wired to each other (scene models
// queue their keyframes' analyses for the events service; where-is places things relative to furniture).
#include "schema/clock.h"
#include "schema/settings.h"
#include "services/audit/audit_service.h"
#include "services/classification/classifier_service.h"
#include "services/events/analysis_queue.h"
#include "services/events/event_service.h"
#include "services/features/feature_service.h"
#include "services/features/keyframe_extraction.h"
#include "services/furniture/furniture_service.h"
#include "services/grid/grid_service.h"
#include "services/jobs/job_service.h"
#include "services/octomap/octomap_keyframe_feed.h"
#include "services/octomap/octomap_service.h"
#include "services/scene/scene_service.h"
#include "services/shapes/shape_service.h"
#include "services/segmentation/furniture_segmentation_service.h"
#include "storage/store.h"

namespace anchordb::services {

struct CapabilityOptions {
  ServiceLimits limits;
  GridDefaults grid;
  SceneLimits scene;
  MergeSettings merge;
  EventSettings events;
  AnalysisQueueSettings analysis;
  FurnitureSettings furniture;
  JobSettings jobs;
  OctomapSettings octomap;
  FeatureSettings features;
  ShapeSettings shapes;
  SegmentationSettings segmentation;
};

// Binds the settings of every capability, in a stable order.
void BindCapabilitySettings(SettingsBinder& b, CapabilityOptions& options);

class Capabilities {
 public:
  // Throws Error(kInvalidArgument) when options.furniture.knowledge_json does not load.
  Capabilities(storage::Store& store, const CapabilityOptions& options, const Clock& clock = SystemClock::Instance());
  Capabilities(const Capabilities&) = delete;
  Capabilities& operator=(const Capabilities&) = delete;

  GridService grid;
  SceneService scenes;
  FurnitureService furniture;
  EventService events;
  AnalysisQueue analysis;  // keyframe analyses queued by `scenes`; its workers run after analysis.Start()
  JobService jobs;
  AuditService audit;
  OctomapService octomap;
  OctomapKeyframeFeed octomap_feed;  // in front of `analysis`: stored keyframes also update the map's tree
  FeatureService features;  // anchored features, codebooks (its job kind registers with `jobs`)
  KeyframeExtraction keyframe_features;  // in front of `analysis`: features of every keyframe, by setting
  ClassifierService classifiers;  // E-SAMME models (its training job kind registers with `jobs`)
  ShapeService shapes;  // 3D shape models (its training job kind registers with `jobs`)
  FurnitureSegmentationService segmentation;  // furniture found in the keyframes (its job kind registers with `jobs`)
};

}  // namespace anchordb::services
