// TRANSITIONAL (see transitional_analysis_json.h).
#include "services/events/transitional_analysis_json.h"

#include "services/events/event_details.h"

namespace anchordb::services {

Json TransitionalAnalysisJson(const KeyframeAnalysis& a) {
  Json events = Json::array();
  for (const EventView& e : a.events) {
    Json evidence = Json::array();
    for (const auto& k : e.evidence) evidence.push_back({{"keyframe", k.keyframe_id}, {"role", k.role}});
    const auto or_null = [](const auto& v) { return v ? Json(*v) : Json(nullptr); };
    events.push_back({{"id", e.id}, {"type", e.type}, {"detection", e.detection}, {"stamp_ns", e.stamp_ns},
                      {"scene", or_null(e.scene_id)}, {"action_layer", or_null(e.action_layer)},
                      {"instance", or_null(e.instance_id)}, {"segment", or_null(e.segment_id)}, {"label", or_null(e.label)},
                      {"explanation", e.explanation}, {"details", Json::parse(EncodeEventDetails(e.details))},
                      {"evidence", evidence}});
  }
  Json out = {{"events", events}, {"segments", a.segments}};
  if (a.action_layer) out["action_layer"] = *a.action_layer;
  return out;
}

}  // namespace anchordb::services
