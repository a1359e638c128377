#include "storage/analysis_queue.h"

namespace anchordb::storage {
namespace {

constexpr const char* kQueueColumns = "keyframe_id, map_id, scene_id, enqueued_ns, attempts, next_attempt_ns, last_error, failed";

QueuedAnalysis RowOf(Statement& s) {
  QueuedAnalysis q;
  q.keyframe_id = s.Int(0);
  q.map_id = s.Text(1);
  q.scene_id = s.Int(2);
  q.enqueued_ns = s.Int(3);
  q.attempts = static_cast<int>(s.Int(4));
  q.next_attempt_ns = s.Int(5);
  if (!s.IsNull(6)) q.last_error = s.Text(6);
  q.failed = s.Int(7) != 0;
  return q;
}

}  // namespace

void EnqueueAnalysis(Connection& c, const QueuedAnalysis& q) {
  Statement(c, "INSERT INTO keyframe_analysis_queue (keyframe_id, map_id, scene_id, enqueued_ns) VALUES (?, ?, ?, ?)")
      .Bind(1, q.keyframe_id).Bind(2, q.map_id).Bind(3, q.scene_id).Bind(4, q.enqueued_ns).Run();
}

std::vector<QueueHead> QueueHeads(Connection& c) {
  // The grouped table names only head and pending, so the queue's columns need no prefix.
  Statement s(c, std::string("SELECT ") + kQueueColumns + ", pending FROM keyframe_analysis_queue JOIN (SELECT "
                 "min(keyframe_id) AS head, count(*) AS pending FROM keyframe_analysis_queue WHERE failed = 0 GROUP BY "
                 "map_id) h ON keyframe_id = h.head ORDER BY keyframe_id");
  std::vector<QueueHead> out;
  while (s.Step()) out.push_back({RowOf(s), s.Int(8)});
  return out;
}

std::int64_t PendingAnalyses(Connection& c, const std::string& map) {
  Statement s(c, "SELECT count(*) FROM keyframe_analysis_queue WHERE map_id = ? AND failed = 0");
  s.Bind(1, map);
  s.Step();
  return s.Int(0);
}

std::optional<QueuedAnalysis> FindQueuedAnalysis(Connection& c, std::int64_t keyframe_id) {
  Statement s(c, std::string("SELECT ") + kQueueColumns + " FROM keyframe_analysis_queue WHERE keyframe_id = ?");
  s.Bind(1, keyframe_id);
  if (!s.Step()) return std::nullopt;
  return RowOf(s);
}

bool DequeueAnalysis(Connection& c, std::int64_t keyframe_id) {
  Statement(c, "DELETE FROM keyframe_analysis_queue WHERE keyframe_id = ?").Bind(1, keyframe_id).Run();
  return c.Changes() == 1;
}

void RecordAnalysisFailure(Connection& c, std::int64_t keyframe_id, const std::string& error, std::int64_t next_attempt_ns,
                           bool give_up) {
  Statement(c, "UPDATE keyframe_analysis_queue SET attempts = attempts + 1, last_error = ?, next_attempt_ns = ?, "
               "failed = ? WHERE keyframe_id = ?")
      .Bind(1, error).Bind(2, next_attempt_ns).Bind(3, static_cast<std::int64_t>(give_up ? 1 : 0)).Bind(4, keyframe_id).Run();
}

AnalysisQueueSummary SummariseAnalysisQueue(Connection& c, const std::optional<std::string>& map, int limit) {
  const std::string where = map ? " WHERE map_id = ?" : "";
  AnalysisQueueSummary out;
  {
    Statement s(c, "SELECT count(CASE WHEN failed = 0 THEN 1 END), count(CASE WHEN failed = 1 THEN 1 END), "
                   "count(CASE WHEN failed = 0 AND attempts > 0 THEN 1 END), "
                   "min(CASE WHEN failed = 0 THEN enqueued_ns END) FROM keyframe_analysis_queue" + where);
    if (map) s.Bind(1, *map);
    s.Step();
    out.pending = s.Int(0);
    out.failed = s.Int(1);
    out.retrying = s.Int(2);
    if (!s.IsNull(3)) out.oldest_enqueued_ns = s.Int(3);
  }
  Statement s(c, std::string("SELECT ") + kQueueColumns + " FROM keyframe_analysis_queue" + (map ? where + " AND" : " WHERE") +
                 " attempts > 0 ORDER BY keyframe_id LIMIT ?");
  int k = 1;
  if (map) s.Bind(k++, *map);
  s.Bind(k, static_cast<std::int64_t>(limit));
  while (s.Step()) out.failures.push_back(RowOf(s));
  return out;
}

}  // namespace anchordb::storage
