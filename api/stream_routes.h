#pragma once
// The live change stream GET /v1/maps/{map}/events:stream (SPEC §4.10, §5): Server-Sent Events of the map's change
// events (`event: change`), labels (`event: label`) and job progress (`event: job`) as they happen.
//
// Every message carries an `id:`: for change and label messages the event's id, for job messages the id of the last
// event sent before it. A client that reconnects with `Last-Event-ID` (EventSource does it by itself), or with
// `?after=<id>`, gets every event after that id from the store first, so nothing is lost or sent twice across a
// reconnect; without either the stream starts after the map's newest event. Job messages show the map's queued and
// running jobs on (re)connect and each later change of their status, stage or progress (of a rounded percent).
//
// Fair serving (SPEC §8): each open stream holds one HTTP worker, so at most EventSettings::Stream::max_streams are
// open at once (one more is refused 503 + Retry-After) and each response ends after max_duration_s with the stream's
// `retry:` delay; the client resumes where it was.
#include "api/router.h"
#include "services/events/event_service.h"
#include "services/jobs/job_service.h"

namespace anchordb::api {

void RegisterStreamRoutes(Router& router, services::EventService& events, services::JobService& jobs);

}  // namespace anchordb::api
