#include "storage/instance_classification_repository.h"

namespace anchordb::storage {
namespace {

// The columns ClassificationRow reads, in its order (the statements below spell them out: GCC 12 warns falsely about
// a std::string built from a constant and a literal in this unity build).
InstanceClassificationRecord ClassificationRow(const Statement& s) {
  InstanceClassificationRecord r;
  r.instance_id = s.Int(0);
  r.map_id = s.Text(1);
  r.classifier = s.Text(2);
  r.label = s.Text(3);
  r.segment_id = OptionalInt(s, 4);
  r.keyframe_id = OptionalInt(s, 5);
  r.stamp_ns = s.Int(6);
  return r;
}

}  // namespace

void UpsertInstanceClassification(Connection& c, const InstanceClassificationRecord& r) {
  Statement s(c,
              "INSERT INTO instance_classifications (instance_id, map_id, classifier, label, segment_id, "
              "keyframe_id, stamp_ns) VALUES (?, ?, ?, ?, ?, ?, ?) ON CONFLICT (instance_id) DO UPDATE SET "
              "classifier = excluded.classifier, label = excluded.label, "
              "segment_id = excluded.segment_id, keyframe_id = excluded.keyframe_id, stamp_ns = excluded.stamp_ns");
  s.Bind(1, r.instance_id).Bind(2, r.map_id).Bind(3, r.classifier).Bind(4, r.label);
  BindOptional(s, 5, r.segment_id);
  BindOptional(s, 6, r.keyframe_id);
  s.Bind(7, r.stamp_ns);
  s.Run();
  Statement clear(c, "DELETE FROM instance_classification_shares WHERE instance_id = ?");
  clear.Bind(1, r.instance_id).Run();
  for (const auto& [label, share] : r.distribution) {
    Statement row(c, "INSERT INTO instance_classification_shares (instance_id, map_id, label, share) VALUES (?, ?, ?, ?)");
    row.Bind(1, r.instance_id).Bind(2, r.map_id).Bind(3, label).Bind(4, share).Run();
  }
}

std::optional<InstanceClassificationRecord> FindInstanceClassification(Connection& c, const std::string& map_id,
                                                                       std::int64_t instance_id) {
  Statement s(c,
              "SELECT instance_id, map_id, classifier, label, segment_id, keyframe_id, stamp_ns "
              "FROM instance_classifications WHERE map_id = ? AND instance_id = ?");
  s.Bind(1, map_id).Bind(2, instance_id);
  if (!s.Step()) return std::nullopt;
  InstanceClassificationRecord r = ClassificationRow(s);
  Statement shares(c, "SELECT label, share FROM instance_classification_shares WHERE instance_id = ?");
  shares.Bind(1, instance_id);
  while (shares.Step()) r.distribution[shares.Text(0)] = shares.Double(1);
  return r;
}

std::optional<SegmentRecord> LatestInstanceSegment(Connection& c, const std::string& map_id, std::int64_t instance_id) {
  Statement s(c,
              "SELECT e.segment_id FROM events e JOIN segments g ON g.id = e.segment_id "
              "WHERE e.map_id = ? AND e.instance_id = ? ORDER BY e.stamp_ns DESC, e.id DESC LIMIT 1");
  s.Bind(1, map_id).Bind(2, instance_id);
  if (!s.Step()) return std::nullopt;
  return FindSegment(c, s.Int(0));
}

}  // namespace anchordb::storage
