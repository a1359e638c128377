#include "storage/forgetting.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>

#include "schema/error.h"
#include "storage/repositories.h"
#include "storage/sqlite.h"

namespace anchordb::storage {
namespace {

// The database's size in pages (SQLite: the file's pages and its free list; PostgreSQL: the database's size in
// blocks, and no free list of its own to report).
std::int64_t PageSize(Connection& c);
std::int64_t PageCount(Connection& c);
std::int64_t FreelistCount(Connection& c);

std::int64_t PragmaInt(Connection& c, const char* sql) {
  Statement s(c, sql);
  return s.Step() ? s.Int(0) : 0;
}

std::int64_t CutoffNs(std::int64_t now_ns, double age_s) {
  const long double cutoff = static_cast<long double>(now_ns) - static_cast<long double>(age_s) * 1e9L;
  if (cutoff <= static_cast<long double>(std::numeric_limits<std::int64_t>::min())) {
    return std::numeric_limits<std::int64_t>::min();
  }
  return static_cast<std::int64_t>(cutoff);
}

std::vector<std::int64_t> Ids(Statement& s) {
  std::vector<std::int64_t> ids;
  while (s.Step()) ids.push_back(s.Int(0));
  return ids;
}

std::int64_t SumBytes(Connection& c, const std::string& sql, std::int64_t id) {
  Statement s(c, sql);
  s.Bind(1, id);
  return s.Step() ? s.Int(0) : 0;
}

// Reports a stage's progress every `every` items (the callback may throw to abort).
class Stage {
 public:
  Stage(const ForgetProgress& progress, std::string_view name, double from, double to, std::size_t total)
      : progress_(progress), name_(name), from_(from), to_(to), total_(total) {
    if (progress_) progress_(name_, from_);
  }
  void Step(std::size_t done) {
    if (progress_ && total_ > 0 && (done % 64 == 0 || done == total_)) {
      progress_(name_, from_ + (to_ - from_) * static_cast<double>(done) / static_cast<double>(total_));
    }
  }

 private:
  const ForgetProgress& progress_;
  std::string_view name_;
  double from_, to_;
  std::size_t total_;
};

// 1. Superseded models whose superseder is stored and whose observation ended: drop the state blobs.
void DropSupersededState(Connection& c, ForgetReport& r, const ForgetProgress& progress) {
  Statement select(c,
                   "SELECT m.id FROM scene_models m WHERE m.map_id = ? AND m.status = 'superseded' "
                   "AND m.ended_ns IS NOT NULL AND m.superseded_by IS NOT NULL "
                   "AND EXISTS (SELECT 1 FROM scene_models s WHERE s.id = m.superseded_by) "
                   "AND (m.background IS NOT NULL OR m.weight IS NOT NULL OR m.labels IS NOT NULL) ORDER BY m.id");
  select.Bind(1, r.map_id);
  const std::vector<std::int64_t> ids = Ids(select);
  Stage stage(progress, "models", 0.0, 0.1, ids.size());
  std::size_t done = 0;
  for (std::int64_t id : ids) {
    r.bytes_freed_estimate += SumBytes(
        c, "SELECT coalesce(length(background), 0) + coalesce(length(weight), 0) + coalesce(length(labels), 0) "
           "FROM scene_models WHERE id = ?", id);
    Statement u(c, "UPDATE scene_models SET background = NULL, weight = NULL, labels = NULL, state_version = 0, "
                   "forgotten_ns = ? WHERE id = ?");
    u.Bind(1, r.now_ns).Bind(2, id).Run();
    r.models_state_dropped.push_back(id);
    stage.Step(++done);
  }
}

// 2. Old events nobody needs.
void DeleteEvents(Connection& c, ForgetReport& r, std::int64_t cutoff, const ForgetRules& rules,
                  const ForgetProgress& progress) {
  // Latest event of an instance: the greatest (stamp_ns, id) among its events that place it (a 'labelled' event
  // names it and is kept anyway; it proves no position).
  const char* kSelect =
      "SELECT e.id, e.pinned, CASE WHEN e.type = 'labelled' THEN 1 ELSE 0 END, coalesce(i.pinned, 0), "
      "  CASE WHEN e.instance_id IS NOT NULL AND e.id = (SELECT l.id FROM events l WHERE l.instance_id = e.instance_id "
      "        AND l.type <> 'labelled' ORDER BY l.stamp_ns DESC, l.id DESC LIMIT 1) THEN 1 ELSE 0 END "
      "FROM events e LEFT JOIN instances i ON i.id = e.instance_id "
      "WHERE e.map_id = ? AND e.stamp_ns < ? ORDER BY e.id";
  Statement select(c, kSelect);
  select.Bind(1, r.map_id).Bind(2, cutoff);
  std::vector<std::int64_t> ids;
  while (select.Step()) {
    const OldEventFacts facts{select.Int(1) != 0, select.Int(2) != 0, select.Int(3) != 0, select.Int(4) != 0};
    switch (rules.event(facts)) {
      case EventKeep::kPinned: ++r.events_kept_pinned; break;
      case EventKeep::kLabelled: ++r.events_kept_labelled; break;
      case EventKeep::kInstancePinned: ++r.events_kept_pinned_instance; break;
      case EventKeep::kLatestOfInstance: ++r.events_kept_latest; break;
      case EventKeep::kForget: ids.push_back(select.Int(0)); break;
    }
  }
  Stage stage(progress, "events", 0.1, 0.3, ids.size());
  std::size_t done = 0;
  for (std::int64_t id : ids) {
    r.bytes_freed_estimate += SumBytes(
        c, "SELECT length(explanation) + coalesce(length(label), 0) + 64 + 8 * 19 + "
           "(SELECT 24 * count(*) FROM event_evidence WHERE event_id = ?1) + "
           "(SELECT coalesce(sum(length(label) + 16), 0) FROM event_label_weights WHERE event_id = ?1) "
           "FROM events WHERE id = ?1", id);
    Statement d(c, "DELETE FROM events WHERE id = ?");  // evidence cascades; instance_history.event_id -> NULL
    d.Bind(1, id).Run();
    r.events_deleted.push_back(id);
    stage.Step(++done);
  }
}

// 3. Old keyframes nobody needs, and their segments that no event uses.
void DeleteKeyframes(Connection& c, ForgetReport& r, std::int64_t cutoff, const ForgetRules& rules,
                     const ForgetProgress& progress) {
  const char* kSelect =
      "SELECT k.id, k.pinned, k.relevance, "
      "  CASE WHEN EXISTS (SELECT 1 FROM event_evidence ev WHERE ev.keyframe_id = k.id) OR "
      "  EXISTS (SELECT 1 FROM segments s JOIN events e ON e.segment_id = s.id WHERE s.keyframe_id = k.id) THEN 1 ELSE 0 END, "
      "  CASE WHEN (m.ended_ns IS NULL OR m.status = 'observing') AND COALESCE(m.last_frame_ns, m.started_ns) >= ?2 "
      "  THEN 1 ELSE 0 END, "
      "  CASE WHEN m.ended_ns IS NULL OR m.status = 'observing' THEN 1 ELSE 0 END "
      "FROM keyframes k JOIN scene_models m ON m.id = k.scene_id "
      "WHERE k.map_id = ?1 AND k.stamp_ns < ?2 ORDER BY k.id";
  Statement select(c, kSelect);
  select.Bind(1, r.map_id).Bind(2, cutoff);
  std::vector<std::int64_t> ids;
  while (select.Step()) {
    const OldKeyframeFacts facts{select.Int(1) != 0, select.Double(2), select.Int(3) != 0, select.Int(5) != 0,
                                 select.Int(4) != 0};
    switch (rules.keyframe(facts, r.policy.keep_relevance_at_least)) {
      case KeyframeKeep::kPinned: ++r.keyframes_kept_pinned; break;
      case KeyframeKeep::kRelevant: ++r.keyframes_kept_relevant; break;
      case KeyframeKeep::kReferenced: ++r.keyframes_kept_referenced; break;
      case KeyframeKeep::kOpenScene: ++r.keyframes_kept_open_scene; break;
      case KeyframeKeep::kForget:
        r.keyframes_of_abandoned_scenes += facts.scene_open ? 1 : 0;  // left observing, no frame within the age
        ids.push_back(select.Int(0));
        break;
    }
  }
  Stage stage(progress, "keyframes", 0.3, 0.85, ids.size());
  std::size_t done = 0;
  for (std::int64_t id : ids) {
    Statement segments(c,
                       "SELECT s.id, length(s.sample) + 96 FROM segments s WHERE s.keyframe_id = ? AND NOT EXISTS "
                       "(SELECT 1 FROM events e WHERE e.segment_id = s.id) ORDER BY s.id");
    segments.Bind(1, id);
    std::vector<std::int64_t> segment_ids;
    while (segments.Step()) {
      segment_ids.push_back(segments.Int(0));
      r.bytes_freed_estimate += segments.Int(1);
    }
    for (std::int64_t s : segment_ids) {
      Statement d(c, "DELETE FROM segments WHERE id = ?");
      d.Bind(1, s).Run();
      r.segments_deleted.push_back(s);
    }
    r.bytes_freed_estimate += SumBytes(c, "SELECT length(depth) + length(background) + 96 FROM keyframes WHERE id = ?", id);
    r.bytes_freed_estimate += SumBytes(c, "SELECT COALESCE(SUM(length(descriptor) + 120), 0) FROM features WHERE keyframe_id = ?", id);
    Statement n(c, "SELECT COUNT(*) FROM features WHERE keyframe_id = ?");  // they go with the keyframe (cascade)
    n.Bind(1, id);
    if (n.Step()) r.features_deleted += n.Int(0);
    Statement d(c, "DELETE FROM keyframes WHERE id = ?");  // a remaining reference fails here (foreign key)
    d.Bind(1, id).Run();
    r.keyframes_deleted.push_back(id);
    stage.Step(++done);
  }
}

// 4. Forgotten superseded models without keyframes: the row goes too (its estimate: the covariance, about 400 bytes
// for the typed camera, pose, parameter and merge report columns and the row's own overhead, and the merge report's
// child rows at 24 bytes a candidate or superseded model and 330 a merged model).
void DeleteEmptyModels(Connection& c, ForgetReport& r, const ForgetProgress& progress) {
  Statement select(c,
                   "SELECT m.id, COALESCE(length(m.pose_covariance), 0) + COALESCE(length(m.pose_covariance_f64), 0) + "
                   "400 + 24 * ((SELECT count(*) FROM scene_merge_candidates c WHERE c.scene_id = m.id) + "
                   "(SELECT count(*) FROM scene_merge_superseded s WHERE s.scene_id = m.id)) + "
                   "330 * (SELECT count(*) FROM scene_merge_models u WHERE u.scene_id = m.id) "
                   "FROM scene_models m WHERE m.map_id = ? AND m.status = 'superseded' AND m.forgotten_ns IS NOT NULL "
                   "AND NOT EXISTS (SELECT 1 FROM keyframes k WHERE k.scene_id = m.id) ORDER BY m.id");
  select.Bind(1, r.map_id);
  std::vector<std::pair<std::int64_t, std::int64_t>> rows;
  while (select.Step()) rows.emplace_back(select.Int(0), select.Int(1));
  Stage stage(progress, "models", 0.85, 0.9, rows.size());
  std::size_t done = 0;
  for (const auto& [id, bytes] : rows) {
    // events.scene_id, instances.last_scene_id and superseded_by of older models become NULL (ON DELETE SET NULL).
    Statement d(c, "DELETE FROM scene_models WHERE id = ?");
    d.Bind(1, id).Run();
    r.models_deleted.push_back(id);
    r.bytes_freed_estimate += bytes;
    stage.Step(++done);
  }
}

// 5. Exact repeats of anchored features (migrations/0012): the newer copy goes.
void DeduplicateFeatures(Connection& c, ForgetReport& r) {
  Statement d(c, "DELETE FROM features WHERE id IN (SELECT f.id FROM features f JOIN features g ON g.map_id = f.map_id "
                 "AND g.type = f.type AND g.id < f.id AND g.x_m = f.x_m AND g.y_m = f.y_m AND g.z_m = f.z_m "
                 "AND g.descriptor = f.descriptor WHERE f.map_id = ?)");
  d.Bind(1, r.map_id).Run();
  r.features_deduplicated = c.Changes();
}

std::string MainFile(Connection& c) {
  const char* name = sqlite3_db_filename(SqliteOf(c).handle(), "main");
  return name ? std::string(name) : std::string();
}

std::int64_t PostgresDatabaseBytes(Connection& c) {
  Statement s(c, "SELECT pg_database_size(current_database())");
  s.Step();
  return s.Int(0);
}

std::int64_t PageSize(Connection& c) {
  if (c.engine() == Engine::kPostgresql) return PragmaInt(c, "SELECT CAST(current_setting('block_size') AS BIGINT)");
  return PragmaInt(c, "PRAGMA page_size");
}

std::int64_t PageCount(Connection& c) {
  if (c.engine() == Engine::kPostgresql) return PostgresDatabaseBytes(c) / PageSize(c);
  return PragmaInt(c, "PRAGMA page_count");
}

std::int64_t FreelistCount(Connection& c) {
  if (c.engine() == Engine::kPostgresql) return 0;
  return PragmaInt(c, "PRAGMA freelist_count");
}

// PostgreSQL: a plain VACUUM (outside any transaction) makes the deleted rows' space reusable without locking out
// readers and writers; the files shrink only where trailing pages became empty (VACUUM FULL would lock the tables).
void PostgresVacuum(Connection& c, ForgetReport& r, const ForgetProgress& progress) {
  if (progress) progress("vacuum", 0.9);
  r.file_bytes_before = PostgresDatabaseBytes(c);
  c.Exec("VACUUM scene_models, keyframes, segments, events, event_evidence, instance_history, features");
  r.vacuum_mode = "postgresql_vacuum";
  r.page_count_after_vacuum = PageCount(c);
  r.freelist_after_vacuum = 0;
  r.file_bytes_after = PostgresDatabaseBytes(c);
  if (progress) progress("vacuum", 1.0);
}

void Vacuum(Connection& c, ForgetReport& r, const ForgetProgress& progress) {
  if (c.engine() == Engine::kPostgresql) return PostgresVacuum(c, r, progress);
  if (progress) progress("vacuum", 0.9);
  const std::string path = MainFile(c);
  r.file_bytes_before = DatabaseFileBytes(path);
  const std::int64_t mode = PragmaInt(c, "PRAGMA auto_vacuum");
  if (mode == 2) {
    Statement s(c, "PRAGMA incremental_vacuum");
    s.Run();
    r.vacuum_mode = "incremental";
  } else if (mode == 1) {
    r.vacuum_mode = "full_auto_vacuum";  // FULL already truncates at every commit
  } else {
    c.Exec("PRAGMA auto_vacuum = INCREMENTAL");
    c.Exec("VACUUM");  // rebuilds the file (atomic: through the WAL) with the new mode
    r.vacuum_mode = "switched_to_incremental";
  }
  {
    Statement s(c, "PRAGMA wal_checkpoint(TRUNCATE)");  // the main file shrinks on disk only at a checkpoint
    s.Run();
  }
  r.page_count_after_vacuum = PragmaInt(c, "PRAGMA page_count");
  r.freelist_after_vacuum = PragmaInt(c, "PRAGMA freelist_count");
  r.file_bytes_after = DatabaseFileBytes(path);
  if (progress) progress("vacuum", 1.0);
}

}  // namespace

std::int64_t DatabaseFileBytes(const std::string& path) {
  std::int64_t total = 0;
  for (const std::string& p : {path, path + "-wal"}) {
    std::error_code ec;
    const auto size = std::filesystem::file_size(p, ec);
    if (!ec) total += static_cast<std::int64_t>(size);
  }
  return total;
}

ForgetReport Forget(Connection& c, const std::string& map_id, const ForgetPolicy& policy, const ForgetRules& rules,
                    std::int64_t now_ns, bool dry_run, const ForgetProgress& progress,
                    const ForgetBeforeCommit& before_commit) {
  if (!rules.event || !rules.keyframe) throw Error(ErrorCode::kInternal, "Forget needs both keep rules");
  if (c.InTransaction()) {
    throw Error(ErrorCode::kInternal, "Forget needs a connection outside any transaction");
  }
  const auto start = std::chrono::steady_clock::now();
  ForgetReport r;
  r.map_id = map_id;
  r.dry_run = dry_run;
  r.now_ns = now_ns;
  r.policy = policy;
  {
    Transaction tx(c);
    if (!FindMap(c, map_id)) throw Error(ErrorCode::kNotFound, "map '" + map_id + "' does not exist", "map");
    r.page_size = PageSize(c);
    r.page_count_before = PageCount(c);
    r.freelist_before = FreelistCount(c);
    if (policy.drop_superseded) DropSupersededState(c, r, progress);
    if (policy.event_max_age_s) DeleteEvents(c, r, CutoffNs(now_ns, *policy.event_max_age_s), rules, progress);
    if (policy.keyframe_max_age_s) DeleteKeyframes(c, r, CutoffNs(now_ns, *policy.keyframe_max_age_s), rules, progress);
    if (policy.drop_superseded) DeleteEmptyModels(c, r, progress);
    DeduplicateFeatures(c, r);
    r.page_count_after = PageCount(c);
    r.freelist_after = FreelistCount(c);
    if (progress) progress(dry_run ? "rollback" : "commit", 0.9);
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!dry_run) {
      r.committed = true;  // as recorded by before_commit; false again if the commit throws
      try {
        if (before_commit) before_commit(c, r);
        tx.Commit();
      } catch (...) {
        r.committed = false;
        throw;
      }
    }
    // A dry run rolls back here (Transaction's destructor).
  }
  if (policy.vacuum) {
    if (dry_run) r.vacuum_mode = "skipped (dry run)";
    else Vacuum(c, r, progress);
  }
  if (progress) progress("done", 1.0);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace anchordb::storage
