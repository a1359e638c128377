#pragma once
// The queue of keyframe analyses (migrations/0009_keyframe_analysis_queue.sql): one row per stored keyframe whose
// change analysis has not been written yet. The scene service inserts a row in the transaction that stores the
// keyframe; the analysis worker deletes it in the transaction that writes the analysis' events. Deleting the keyframe
// (or its scene or map) deletes its row by foreign key. Errors: anchordb::Error from storage/sqlite.h.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "storage/connection.h"

namespace anchordb::storage {

struct QueuedAnalysis {
  std::int64_t keyframe_id = 0;
  std::string map_id;
  std::int64_t scene_id = 0;
  std::int64_t enqueued_ns = 0;      // when the keyframe was stored [ns since the epoch]
  int attempts = 0;                  // failed attempts so far
  std::int64_t next_attempt_ns = 0;  // not before this instant (backoff)
  std::optional<std::string> last_error;
  bool failed = false;               // given up: kept for the operator, skipped by the worker
};

void EnqueueAnalysis(Connection& c, const QueuedAnalysis& row);
// The head of a map's queue (its oldest keyframe not given up) and how many of the map's rows are not given up.
struct QueueHead {
  QueuedAnalysis row;
  std::int64_t map_pending = 0;
};
// The head of every map's queue, oldest keyframe first: the worker's candidates. The head of a map whose
// next_attempt_ns is in the future blocks that map (analyses of one map run in order).
std::vector<QueueHead> QueueHeads(Connection& c);
// The rows of `map` not given up (queued or running).
std::int64_t PendingAnalyses(Connection& c, const std::string& map);
std::optional<QueuedAnalysis> FindQueuedAnalysis(Connection& c, std::int64_t keyframe_id);
// Deletes the row; false when it was gone (its keyframe was deleted).
bool DequeueAnalysis(Connection& c, std::int64_t keyframe_id);
// Records a failed attempt: attempts + 1, the error, the next attempt's time; `give_up` marks it failed.
void RecordAnalysisFailure(Connection& c, std::int64_t keyframe_id, const std::string& error, std::int64_t next_attempt_ns,
                           bool give_up);

// One map's queue for the operator (nullopt map: all maps).
struct AnalysisQueueSummary {
  std::int64_t pending = 0;                       // rows not given up
  std::int64_t failed = 0;                        // rows given up
  std::int64_t retrying = 0;                      // pending rows with at least one failed attempt
  std::optional<std::int64_t> oldest_enqueued_ns;  // of the pending rows
  std::vector<QueuedAnalysis> failures;           // rows with a failed attempt, oldest first (at most `limit`)
};
AnalysisQueueSummary SummariseAnalysisQueue(Connection& c, const std::optional<std::string>& map, int limit = 20);

}  // namespace anchordb::storage
