#include "storage/event_repository.h"

#include <algorithm>
#include <unordered_map>

#include "storage/dialect.h"
#include "storage/event_details_columns.h"
#include "schema/error.h"

namespace anchordb::storage {
namespace {

constexpr const char* kSegmentColumns =
    "id, map_id, keyframe_id, x_m, y_m, z_m, min_x_m, min_y_m, min_z_m, max_x_m, max_y_m, max_z_m, points, sample";

constexpr const char* kInstanceColumns =
    "id, map_id, kind, status, label_locked, status_locked, pinned, x_m, y_m, z_m, extent_x_m, extent_y_m, "
    "extent_z_m, yaw_rad, last_seen_ns, last_scene_id, created_ns, updated_ns";

// "a, b" -> "p.a, p.b"
std::string Qualified(std::string_view columns, std::string_view prefix) {
  std::string out(prefix);
  for (const char ch : columns) {
    out += ch;
    if (ch == ' ') out += prefix;
  }
  return out;
}

int ColumnCount(std::string_view columns) { return static_cast<int>(std::count(columns.begin(), columns.end(), ',')) + 1; }

// ", NULL" `n` times: the padding of a UNION ALL part for columns it does not have.
std::string Nulls(int n) {
  std::string out;
  for (; n > 0; --n) out += ", NULL";
  return out;
}

constexpr std::size_t kMaxWhereFurniture = 10000;

// An instance from kInstanceColumns starting at column `at` (then the sample when asked for), without its labels.
InstanceRecord ReadInstance(const Statement& s, bool with_sample, int at = 0) {
  InstanceRecord r;
  r.id = s.Int(at + 0);
  r.map_id = s.Text(at + 1);
  r.kind = s.Text(at + 2);
  r.status = s.Text(at + 3);
  r.label_locked = s.Int(at + 4) != 0;
  r.status_locked = s.Int(at + 5) != 0;
  r.pinned = s.Int(at + 6) != 0;
  for (int k = 0; k < 3; ++k) r.position[k] = s.Double(at + 7 + k), r.extent[k] = s.Double(at + 10 + k);
  r.yaw_rad = s.Double(at + 13);
  r.last_seen_ns = s.Int(at + 14);
  r.last_scene_id = OptionalInt(s, at + 15);
  r.created_ns = s.Int(at + 16);
  r.updated_ns = s.Int(at + 17);
  if (with_sample && !s.IsNull(at + 18)) r.sample = s.Blob(at + 18);
  return r;
}

// Instances read with `LEFT JOIN instance_labels AS l` (kLabelColumns last, from `label_at`): one row per label, a
// row with NULLs for an instance without any. Rows of one instance follow each other (the statements order by id).
constexpr const char* kLabelColumns = "l.label, l.weight";
void ReadInstanceRow(const Statement& s, bool with_sample, int label_at, std::vector<InstanceRecord>& out) {
  if (out.empty() || out.back().id != s.Int(0)) out.push_back(ReadInstance(s, with_sample));
  if (!s.IsNull(label_at)) out.back().labels[s.Text(label_at)] = s.Double(label_at + 1);
}

void InsertLabels(Connection& c, std::int64_t instance_id, const std::string& map_id,
                  const std::map<std::string, double>& labels) {
  for (const auto& [label, weight] : labels) {
    Statement s(c, "INSERT INTO instance_labels (instance_id, map_id, label, weight) VALUES (?, ?, ?, ?)");
    s.Bind(1, instance_id).Bind(2, map_id).Bind(3, label).Bind(4, weight).Run();
  }
}

// The instance's labels become `labels`; unchanged ones are not written again (most updates move an instance, and
// every label row written counts as a change of the map's instances, migration 0028).
void ReplaceLabels(Connection& c, std::int64_t instance_id, const std::map<std::string, double>& labels) {
  Statement read(c, "SELECT i.map_id, l.label, l.weight FROM instances AS i "
                    "LEFT JOIN instance_labels AS l ON l.instance_id = i.id WHERE i.id = ?");
  read.Bind(1, instance_id);
  std::string map_id;
  std::map<std::string, double> stored;
  while (read.Step()) {
    map_id = read.Text(0);
    if (!read.IsNull(1)) stored[read.Text(1)] = read.Double(2);
  }
  if (map_id.empty() || stored == labels) return;  // no such instance, or nothing to change
  Statement clear(c, "DELETE FROM instance_labels WHERE instance_id = ?");
  clear.Bind(1, instance_id).Run();
  InsertLabels(c, instance_id, map_id, labels);
}

// The event's own columns, then its detail columns (event_details_columns.h) from kEventDetailsAt.
const std::string kEventColumns =
    std::string("id, map_id, type, detection, stamp_ns, scene_id, action_layer, instance_id, segment_id, label, "
                "explanation, pinned, created_ns, ") + event_details::kColumns;
constexpr int kEventDetailsAt = 13;

struct EventRow {
  EventRecord event;
  std::int64_t label_weight_rows = 0;  // still to load
};

EventRow ReadEvent(const Statement& s) {
  EventRow row;
  EventRecord& e = row.event;
  e.id = s.Int(0);
  e.map_id = s.Text(1);
  e.type = s.Text(2);
  e.detection = s.Text(3);
  e.stamp_ns = s.Int(4);
  e.scene_id = OptionalInt(s, 5);
  e.action_layer = OptionalInt(s, 6);
  e.instance_id = OptionalInt(s, 7);
  e.segment_id = OptionalInt(s, 8);
  if (!s.IsNull(9)) e.label = s.Text(9);
  e.explanation = s.Text(10);
  e.pinned = s.Int(11) != 0;
  e.created_ns = s.Int(12);
  row.label_weight_rows = event_details::Read(s, kEventDetailsAt, e.details);
  return row;
}

void LoadEvidence(Connection& c, EventRecord& e) {
  Statement s(c, "SELECT keyframe_id, role FROM event_evidence WHERE event_id = ? ORDER BY role DESC, keyframe_id");
  s.Bind(1, e.id);
  while (s.Step()) e.evidence.push_back({s.Int(0), s.Text(1)});
}

// The evidence keyframes and the label weights of an event read by ReadEvent.
EventRecord Complete(Connection& c, EventRow row) {
  LoadEvidence(c, row.event);
  if (row.label_weight_rows > 0) event_details::LoadLabelWeights(c, row.event.id, row.event.details);
  return std::move(row.event);
}

}  // namespace

std::int64_t InsertSegment(Connection& c, const SegmentRecord& r) {
  Statement s(c, "INSERT INTO segments (map_id, keyframe_id, x_m, y_m, z_m, min_x_m, min_y_m, min_z_m, max_x_m, max_y_m, "
                 "max_z_m, points, sample) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?) RETURNING id");
  s.Bind(1, r.map_id).Bind(2, r.keyframe_id);
  for (int k = 0; k < 3; ++k) s.Bind(3 + k, r.centroid[k]).Bind(6 + k, r.min[k]).Bind(9 + k, r.max[k]);
  s.Bind(12, r.points).BindBlob(13, r.sample);
  return s.RunReturningId();
}

std::optional<SegmentRecord> FindSegment(Connection& c, std::int64_t id) {
  Statement s(c, std::string("SELECT ") + kSegmentColumns + " FROM segments WHERE id = ?");
  s.Bind(1, id);
  if (!s.Step()) return std::nullopt;
  SegmentRecord r;
  r.id = s.Int(0);
  r.map_id = s.Text(1);
  r.keyframe_id = s.Int(2);
  for (int k = 0; k < 3; ++k) r.centroid[k] = s.Double(3 + k), r.min[k] = s.Double(6 + k), r.max[k] = s.Double(9 + k);
  r.points = s.Int(12);
  r.sample = s.Blob(13);
  return r;
}

std::int64_t InsertInstance(Connection& c, const InstanceRecord& r) {
  Statement s(c, "INSERT INTO instances (map_id, kind, status, label_locked, status_locked, pinned, x_m, y_m, z_m, "
                 "extent_x_m, extent_y_m, extent_z_m, yaw_rad, last_seen_ns, last_scene_id, created_ns, updated_ns, sample) "
                 "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?) RETURNING id");
  s.Bind(1, r.map_id).Bind(2, r.kind).Bind(3, r.status).Bind(4, static_cast<std::int64_t>(r.label_locked))
      .Bind(5, static_cast<std::int64_t>(r.status_locked)).Bind(6, static_cast<std::int64_t>(r.pinned));
  for (int k = 0; k < 3; ++k) s.Bind(7 + k, r.position[k]).Bind(10 + k, r.extent[k]);
  s.Bind(13, r.yaw_rad).Bind(14, r.last_seen_ns);
  BindOptional(s, 15, r.last_scene_id);
  s.Bind(16, r.created_ns).Bind(17, r.updated_ns);
  if (r.sample.empty()) s.BindNull(18); else s.BindBlob(18, r.sample);
  const std::int64_t id = s.RunReturningId();
  InsertLabels(c, id, r.map_id, r.labels);
  return id;
}

void UpdateInstance(Connection& c, const InstanceRecord& r) {
  Statement s(c, "UPDATE instances SET kind = ?, status = ?, label_locked = ?, status_locked = ?, pinned = ?, "
                 "x_m = ?, y_m = ?, z_m = ?, extent_x_m = ?, extent_y_m = ?, extent_z_m = ?, yaw_rad = ?, last_seen_ns = ?, "
                 "last_scene_id = ?, updated_ns = ?, sample = COALESCE(?, sample) WHERE id = ?");
  s.Bind(1, r.kind).Bind(2, r.status).Bind(3, static_cast<std::int64_t>(r.label_locked))
      .Bind(4, static_cast<std::int64_t>(r.status_locked)).Bind(5, static_cast<std::int64_t>(r.pinned));
  for (int k = 0; k < 3; ++k) s.Bind(6 + k, r.position[k]).Bind(9 + k, r.extent[k]);
  s.Bind(12, r.yaw_rad).Bind(13, r.last_seen_ns);
  BindOptional(s, 14, r.last_scene_id);
  s.Bind(15, r.updated_ns);
  if (r.sample.empty()) s.BindNull(16); else s.BindBlob(16, r.sample);
  s.Bind(17, r.id).Run();
  ReplaceLabels(c, r.id, r.labels);
}

std::optional<InstanceRecord> FindInstance(Connection& c, const std::string& map_id, std::int64_t id, bool with_sample) {
  Statement s(c, "SELECT " + Qualified(kInstanceColumns, "i.") + (with_sample ? ", i.sample, " : ", ") + kLabelColumns +
                     " FROM instances AS i LEFT JOIN instance_labels AS l ON l.instance_id = i.id"
                     " WHERE i.map_id = ? AND i.id = ?");
  s.Bind(1, map_id).Bind(2, id);
  std::vector<InstanceRecord> out;
  const int label_at = ColumnCount(kInstanceColumns) + (with_sample ? 1 : 0);
  while (s.Step()) ReadInstanceRow(s, with_sample, label_at, out);
  if (out.empty()) return std::nullopt;
  return std::move(out.front());
}

std::vector<InstanceRecord> ListInstances(Connection& c, const std::string& map_id, const InstanceFilter& f,
                                          bool with_sample) {
  // The page of instances first (ORDER BY id LIMIT), then their label rows joined to it.
  std::string page = std::string("SELECT ") + kInstanceColumns + (with_sample ? ", sample" : "") +
                     " FROM instances WHERE map_id = ?1 AND id > ?2";
  if (f.kind) page += " AND kind = ?3";
  if (f.status) page += " AND status = ?4";
  else if (!f.include_deleted) page += " AND status != 'deleted'";
  if (f.label && !f.label_from_classifier) {
    page += " AND id IN (SELECT instance_id FROM instance_labels WHERE map_id = ?1 AND label = ?6)";
  } else if (f.label) {
    // One IN list (an OR of two would make SQLite scan the map's instances).
    page += " AND id IN (SELECT instance_id FROM instance_labels WHERE map_id = ?1 AND label = ?6"
            " UNION SELECT k.instance_id FROM instance_classification_shares AS k"
            " WHERE k.map_id = ?1 AND k.label = ?6 AND k.share > 0 AND ?6 != 'unknown'"
            " AND k.instance_id NOT IN (SELECT instance_id FROM instance_labels WHERE map_id = ?1))";
  }
  page += " ORDER BY id LIMIT ?5";
  Statement s(c, "SELECT " + Qualified(kInstanceColumns, "i.") + (with_sample ? ", i.sample, " : ", ") + kLabelColumns +
                     " FROM (" + page + ") AS i LEFT JOIN instance_labels AS l ON l.instance_id = i.id ORDER BY i.id");
  s.Bind(1, map_id).Bind(2, f.after_id).Bind(5, static_cast<std::int64_t>(f.limit));
  if (f.kind) s.Bind(3, *f.kind);
  if (f.status) s.Bind(4, *f.status);
  if (f.label) s.Bind(6, *f.label);
  std::vector<InstanceRecord> out;
  const int label_at = ColumnCount(kInstanceColumns) + (with_sample ? 1 : 0);
  while (s.Step()) ReadInstanceRow(s, with_sample, label_at, out);
  return out;
}

std::int64_t InstanceVersion(Connection& c, const std::string& map_id) {
  Statement s(c, "SELECT version FROM map_instance_versions WHERE map_id = ?");
  s.Bind(1, map_id);
  return s.Step() ? s.Int(0) : 0;
}

namespace {
// The parts of a map's where-is stamp (map ?1), one scalar subquery each: read alone by ReadWhereStamp and inside
// ReadWhereInputs' statement.
constexpr const char* kStampCreated = "(SELECT created_ns FROM maps WHERE id = ?1)";
constexpr const char* kStampVersion = "(SELECT version FROM map_instance_versions WHERE map_id = ?1)";
constexpr const char* kStampGraph = "(SELECT MAX(id) FROM furniture_graphs WHERE map_id = ?1)";
}  // namespace

WhereStamp ReadWhereStamp(Connection& c, const std::string& map_id) {
  Statement s(c, std::string("SELECT ") + kStampCreated + ", " + kStampVersion + ", " + kStampGraph);
  s.Bind(1, map_id);
  WhereStamp out;
  if (!s.Step()) return out;
  out.map_created_ns = OptionalInt(s, 0);
  out.instance_version = OptionalInt(s, 1).value_or(0);
  out.newest_graph_id = OptionalInt(s, 2);
  return out;
}

void AppendHistory(Connection& c, const HistoryRecord& h) {
  Statement s(c, "INSERT INTO instance_history (instance_id, seq, stamp_ns, present, x_m, y_m, z_m, event_id) "
                 "VALUES (?1, (SELECT COALESCE(MAX(seq), 0) + 1 FROM instance_history WHERE instance_id = ?1), ?2, ?3, ?4, "
                 "?5, ?6, ?7)");
  s.Bind(1, h.instance_id).Bind(2, h.stamp_ns).Bind(3, static_cast<std::int64_t>(h.present))
      .Bind(4, h.position[0]).Bind(5, h.position[1]).Bind(6, h.position[2]);
  BindOptional(s, 7, h.event_id);
  s.Run();
}

namespace {
// A history entry from kHistoryColumns starting at column `at`.
HistoryRecord ReadHistory(const Statement& s, int at = 0) {
  HistoryRecord h;
  h.instance_id = s.Int(at + 0);
  h.seq = s.Int(at + 1);
  h.stamp_ns = s.Int(at + 2);
  h.present = s.Int(at + 3) != 0;
  for (int k = 0; k < 3; ++k) h.position[k] = s.Double(at + 4 + k);
  h.event_id = OptionalInt(s, at + 7);
  return h;
}
constexpr const char* kHistoryColumns = "instance_id, seq, stamp_ns, present, x_m, y_m, z_m, event_id";
}  // namespace

std::vector<HistoryRecord> ListHistory(Connection& c, std::int64_t instance_id) {
  Statement s(c, std::string("SELECT ") + kHistoryColumns + " FROM instance_history WHERE instance_id = ? ORDER BY seq");
  s.Bind(1, instance_id);
  std::vector<HistoryRecord> out;
  while (s.Step()) out.push_back(ReadHistory(s));
  return out;
}

std::optional<HistoryRecord> HistoryAt(Connection& c, std::int64_t instance_id, std::int64_t at_ns) {
  Statement s(c, std::string("SELECT ") + kHistoryColumns +
                     " FROM instance_history WHERE instance_id = ? AND stamp_ns <= ? ORDER BY stamp_ns DESC, seq DESC LIMIT 1");
  s.Bind(1, instance_id).Bind(2, at_ns);
  if (!s.Step()) return std::nullopt;
  return ReadHistory(s);
}

WhereInputs ReadWhereInputs(Connection& c, const std::string& map_id, const std::string& label, std::int64_t at_ns) {
  // Five parts in one UNION ALL, told apart by the first column: 0 a labelled object and its history entry at the
  // time (instance columns from 1, history columns after them), 1 a piece of furniture, 2 the newest graph id, 3 the
  // map's instance version, 4 the map's creation time (2-4 in column 1, the stamp's parts); parts 0 and 1 are one
  // row per label of the instance (label and weight last). No ORDER BY: the rows
  // are put in order here, which spares PostgreSQL's executor two sort nodes and a subquery scan per call (measured
  // with pgbench: about a fifth of the statement's cost on the where-is benchmark's map).
  const int history_columns = ColumnCount(kHistoryColumns);
  const std::string tail_nulls = Nulls(ColumnCount(kInstanceColumns) - 1) + Nulls(history_columns) + Nulls(2);
  const std::string sql =
      "SELECT 0, " + Qualified(kInstanceColumns, "i.") + ", " + Qualified(kHistoryColumns, "h.") + ", " + kLabelColumns +
      " FROM instances AS i LEFT JOIN instance_history AS h ON h.instance_id = i.id AND h.seq = ("
      "SELECT h2.seq FROM instance_history AS h2 WHERE h2.instance_id = i.id AND h2.stamp_ns <= ?3"
      " ORDER BY h2.stamp_ns DESC, h2.seq DESC LIMIT 1) LEFT JOIN instance_labels AS l ON l.instance_id = i.id"
      " WHERE i.map_id = ?1 AND i.kind = 'object' AND i.status != 'deleted'"
      " AND i.id IN (SELECT instance_id FROM instance_labels WHERE map_id = ?1 AND label = ?2)"
      " UNION ALL SELECT 1, " + Qualified(kInstanceColumns, "i.") + Nulls(history_columns) + ", " + kLabelColumns +
      " FROM instances AS i LEFT JOIN instance_labels AS l ON l.instance_id = i.id"
      " WHERE i.map_id = ?1 AND i.kind = 'furniture' AND i.status != 'deleted'"
      " UNION ALL SELECT 2, " + kStampGraph + tail_nulls + " UNION ALL SELECT 3, " + kStampVersion + tail_nulls +
      " UNION ALL SELECT 4, " + kStampCreated + tail_nulls;
  Statement s(c, sql);
  s.Bind(1, map_id).Bind(2, label).Bind(3, at_ns);
  WhereInputs out;
  constexpr int kInstanceAt = 1;
  const int history_at = kInstanceAt + ColumnCount(kInstanceColumns);
  const int label_at = history_at + history_columns;
  std::unordered_map<std::int64_t, std::size_t> labelled_at, furniture_at;  // instance id -> index in out
  while (s.Step()) {
    const std::int64_t part = s.Int(0);
    InstanceRecord* instance = nullptr;
    if (part == 0) {
      const auto [at, added] = labelled_at.try_emplace(s.Int(kInstanceAt), out.labelled.size());
      if (added) {
        WhereCandidateRecord r{ReadInstance(s, false, kInstanceAt), std::nullopt};
        if (!s.IsNull(history_at)) r.position = ReadHistory(s, history_at);
        out.labelled.push_back(std::move(r));
      }
      instance = &out.labelled[at->second].instance;
    } else if (part == 1) {
      const auto [at, added] = furniture_at.try_emplace(s.Int(kInstanceAt), out.furniture.size());
      if (added) out.furniture.push_back(ReadInstance(s, false, kInstanceAt));
      instance = &out.furniture[at->second];
    } else if (part == 2) {
      out.stamp.newest_graph_id = OptionalInt(s, kInstanceAt);
    } else if (part == 3) {
      out.stamp.instance_version = OptionalInt(s, kInstanceAt).value_or(0);
    } else {
      out.stamp.map_created_ns = OptionalInt(s, kInstanceAt);
    }
    if (instance && !s.IsNull(label_at)) instance->labels[s.Text(label_at)] = s.Double(label_at + 1);
  }
  std::sort(out.labelled.begin(), out.labelled.end(),
            [](const WhereCandidateRecord& a, const WhereCandidateRecord& b) { return a.instance.id < b.instance.id; });
  std::sort(out.furniture.begin(), out.furniture.end(),
            [](const InstanceRecord& a, const InstanceRecord& b) { return a.id < b.id; });
  if (out.furniture.size() > kMaxWhereFurniture) out.furniture.resize(kMaxWhereFurniture);
  return out;
}

std::int64_t InsertEvent(Connection& c, const EventRecord& e) {
  std::string placeholders = "?";
  for (int i = 1; i < 12 + event_details::kColumnCount; ++i) placeholders += ", ?";
  Statement s(c, "INSERT INTO events (map_id, type, detection, stamp_ns, scene_id, action_layer, instance_id, segment_id, "
                 "label, explanation, pinned, created_ns, " + std::string(event_details::kColumns) + ") VALUES (" +
                     placeholders + ") RETURNING id");
  s.Bind(1, e.map_id).Bind(2, e.type).Bind(3, e.detection).Bind(4, e.stamp_ns);
  BindOptional(s, 5, e.scene_id);
  BindOptional(s, 6, e.action_layer);
  BindOptional(s, 7, e.instance_id);
  BindOptional(s, 8, e.segment_id);
  if (e.label) s.Bind(9, *e.label); else s.BindNull(9);
  s.Bind(10, e.explanation).Bind(11, static_cast<std::int64_t>(e.pinned)).Bind(12, e.created_ns);
  event_details::Bind(s, 13, e.details);
  const std::int64_t id = s.RunReturningId();
  event_details::InsertLabelWeights(c, id, e.details);
  for (const auto& ev : e.evidence) {
    Statement(c, "INSERT INTO event_evidence (event_id, keyframe_id, role) VALUES (?, ?, ?) ON CONFLICT DO NOTHING")
        .Bind(1, id).Bind(2, ev.keyframe_id).Bind(3, ev.role).Run();
  }
  return id;
}

std::optional<EventRecord> FindEvent(Connection& c, const std::string& map_id, std::int64_t id) {
  std::optional<EventRow> row;
  {
    Statement s(c, "SELECT " + kEventColumns + " FROM events WHERE map_id = ? AND id = ?");
    s.Bind(1, map_id).Bind(2, id);
    if (!s.Step()) return std::nullopt;
    row = ReadEvent(s);
  }
  return Complete(c, std::move(*row));
}

std::vector<EventRecord> ListEvents(Connection& c, const std::string& map_id, const EventFilter& f) {
  std::string sql = "SELECT " + kEventColumns + " FROM events WHERE map_id = ?1 AND id > ?2";
  if (f.since_ns) sql += " AND stamp_ns >= ?3";
  if (f.until_ns) sql += " AND stamp_ns <= ?4";
  if (f.type) sql += " AND type = ?5";
  if (f.instance_id) sql += " AND instance_id = ?6";
  if (f.scene_id) sql += " AND scene_id = ?7";
  sql += " ORDER BY id LIMIT ?8";
  Statement s(c, sql);
  s.Bind(1, map_id).Bind(2, f.after_id).Bind(8, static_cast<std::int64_t>(f.limit));
  if (f.since_ns) s.Bind(3, *f.since_ns);
  if (f.until_ns) s.Bind(4, *f.until_ns);
  if (f.type) s.Bind(5, *f.type);
  if (f.instance_id) s.Bind(6, *f.instance_id);
  if (f.scene_id) s.Bind(7, *f.scene_id);
  std::vector<EventRow> rows;
  while (s.Step()) rows.push_back(ReadEvent(s));
  std::vector<EventRecord> out;
  out.reserve(rows.size());
  for (EventRow& row : rows) out.push_back(Complete(c, std::move(row)));
  return out;
}

std::int64_t MaxEventId(Connection& c, const std::string& map_id) {
  Statement s(c, "SELECT COALESCE(MAX(id), 0) FROM events WHERE map_id = ?");
  s.Bind(1, map_id);
  return s.Step() ? s.Int(0) : 0;
}

void SetEventInstance(Connection& c, std::int64_t event_id, std::int64_t instance_id) {
  Statement(c, "UPDATE events SET instance_id = ? WHERE id = ?").Bind(1, instance_id).Bind(2, event_id).Run();
}

bool DeleteEvent(Connection& c, const std::string& map_id, std::int64_t event_id) {
  Statement(c, "DELETE FROM events WHERE map_id = ? AND id = ?").Bind(1, map_id).Bind(2, event_id).Run();
  return c.Changes() > 0;
}

std::optional<std::int64_t> LatestKeyframeId(Connection& c, std::int64_t scene_id) {
  Statement s(c, "SELECT id FROM keyframes WHERE scene_id = ? ORDER BY stamp_ns DESC, id DESC LIMIT 1");
  s.Bind(1, scene_id);
  if (!s.Step()) return std::nullopt;
  return s.Int(0);
}

std::optional<std::int64_t> PreviousKeyframeId(Connection& c, std::int64_t scene_id, std::int64_t keyframe_id) {
  Statement s(c, "SELECT id FROM keyframes WHERE scene_id = ? AND id < ? ORDER BY id DESC LIMIT 1");
  s.Bind(1, scene_id).Bind(2, keyframe_id);
  if (!s.Step()) return std::nullopt;
  return s.Int(0);
}

bool SetKeyframePinned(Connection& c, const std::string& map_id, std::int64_t id, bool pinned) {
  Statement(c, "UPDATE keyframes SET pinned = ? WHERE map_id = ? AND id = ?")
      .Bind(1, static_cast<std::int64_t>(pinned)).Bind(2, map_id).Bind(3, id).Run();
  return c.Changes() == 1;
}

bool SetKeyframeRelevance(Connection& c, const std::string& map_id, std::int64_t id, double relevance) {
  Statement(c, "UPDATE keyframes SET relevance = ? WHERE map_id = ? AND id = ?").Bind(1, relevance).Bind(2, map_id).Bind(3, id).Run();
  return c.Changes() == 1;
}

std::int64_t KeyframeReferences(Connection& c, std::int64_t id) {
  Statement s(c, "SELECT (SELECT COUNT(*) FROM event_evidence WHERE keyframe_id = ?1) + "
                 "(SELECT COUNT(*) FROM segments WHERE keyframe_id = ?1)");
  s.Bind(1, id);
  s.Step();
  return s.Int(0);
}

}  // namespace anchordb::storage
