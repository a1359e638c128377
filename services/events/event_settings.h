#pragma once
// The settings of change detection, instance matching and the lost-key rule, bound once to EventSettings.
#include "schema/settings.h"
#include "services/events/analysis_queue.h"
#include "services/events/event_service.h"

namespace anchordb::services {

void BindEventSettings(SettingsBinder& b, EventSettings& events);
// analysis_threads, analysis_wait_max_s, analysis_retry_initial_s, analysis_retry_max_s, analysis_max_attempts.
void BindAnalysisQueueSettings(SettingsBinder& b, AnalysisQueueSettings& analysis);

}  // namespace anchordb::services
