#pragma once
// JSON <-> the typed requests and results of the event service (SPEC §4.4, §5): change events, instances, the
// where-is answer and keyframe operations. Parse errors are Error(kInvalidArgument) naming the field.
#include "api/http_api.h"  // Eigen before httplib
#include "services/events/event_types.h"
#include "services/events/analysis_queue.h"
#include "services/scene/keyframe_listener.h"
#include "services/scene/scene_types.h"

namespace anchordb::api {

// Requests.
services::EventQuery ParseEventQuery(const httplib::Request& req);        // since, until, type, instance, scene, after, limit
services::InstanceQuery ParseInstanceQuery(const httplib::Request& req);  // label, kind, status, after, limit
services::WhereRequest ParseWhereRequest(const httplib::Request& req);    // label (required), at
services::LabelRequest ParseLabelRequest(const Json& body);               // {label, source}
services::CreateInstanceRequest ParseCreateInstanceRequest(const Json& body);  // {kind, label, position, extent, yaw_rad, stamp}
double ParseRelevance(const Json& body);                                  // {relevance}
services::ReanalyseRequest ParseReanalyseRequest(const Json& body);       // {scene}

// Results.
Json EventJson(const services::EventView& e);
Json EventPageJson(const services::EventPage& page);
Json InstanceJson(const services::InstanceView& r);
Json InstancePageJson(const services::InstancePage& page);
Json HistoryJson(const services::InstanceHistory& h);
Json LabelResultJson(const services::LabelResult& r);
Json WhereJson(const services::WhereAnswer& a);
Json KeyframePinnedJson(const services::KeyframePinned& k);
Json KeyframeRelevanceJson(const services::KeyframeRelevance& k);
Json ReanalyseJson(const services::ReanalyseResult& r);
// The "analysis" of a frame or keyframe response: {events, segments, action_layer (when a layer was closed)}.
Json KeyframeAnalysisJson(const services::KeyframeAnalysis& a);
// The "analysis" of a response that stored a keyframe: {state, keyframe_id} (pending unless the request waited), with
// the KeyframeAnalysisJson fields when done in this process, attempts and last_error after a failed attempt.
Json KeyframeAnalysisStatusJson(const services::KeyframeAnalysisStatus& s);
// GET /v1/maps/{map}/analysis: the map's analysis queue.
Json AnalysisQueueJson(const services::AnalysisQueueView& v);
// Prometheus text of the analysis queue (appended to GET /metrics).
std::string AnalysisMetricsText(const services::AnalysisQueueView& all, const services::AnalysisCounters& counters);

}  // namespace anchordb::api
