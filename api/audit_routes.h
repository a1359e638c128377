#pragma once
// The audit trail at the HTTP edge (SPEC §8) and its route GET /v1/audit (admin).
// Audited: every write (not GET) made with an admin token, and the editing actions of an operator whatever the role
// (labels of instances and events, pins, instance creation and deletion, keyframe relevance, map and layer
// deletion, forgetting (dry runs too: they are admin requests), backups). Not audited: the robot's bulk writes
// (frames, observations, agents) and requests refused before their handler (401/403, 400 of a malformed path:
// the request log has them). Each entry holds the caller (token id and role, "loopback" when auth is off), the
// action, the map and resource, the request id, the answer's status, and the changed record before and after the
// handler, read through the resource's GET route. Audited edits run one at a time so their before / after pairs do
// not interleave; the entry is committed after the change, in its own transaction.
#include <string>
#include <vector>

#include "api/router.h"
#include "services/audit/audit_service.h"

namespace anchordb::api {

// One editing action of the table above.
struct AuditedAction {
  const char* method;
  const char* pattern;
  const char* action;             // "instance.label"
  const char* snapshot_pattern;   // GET route reading the changed record before / after, or nullptr
  bool response_is_after = false; // the answer (a created record, a job) is the "after"
};
const std::vector<AuditedAction>& AuditedActions();

// Registers GET /v1/audit and installs the audit trail as the router's request observer. Call after every other
// capability registered its routes.
void RegisterAuditRoutes(Router& router, services::AuditService& audit);

}  // namespace anchordb::api
