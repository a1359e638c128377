#include "storage/furniture_instance_repository.h"

#include <map>

namespace anchordb::storage {
namespace {

constexpr const char* kFurnitureColumns =
    "instance_id, map_id, classifier, min_z_m, height_m, observations, job_id, created_ns, updated_ns";

FurnitureInstanceRecord Row(const Statement& s, bool with_cloud) {
  FurnitureInstanceRecord r;
  r.instance_id = s.Int(0);
  r.map_id = s.Text(1);
  r.classifier = s.Text(2);
  r.min_z_m = s.Double(3);
  r.height_m = s.Double(4);
  r.observations = s.Int(5);
  if (!s.IsNull(6)) r.job_id = s.Int(6);
  r.created_ns = s.Int(7);
  r.updated_ns = s.Int(8);
  if (with_cloud) r.cloud = s.Blob(9);
  return r;
}

std::string Select(bool with_cloud) { return std::string("SELECT ") + kFurnitureColumns + (with_cloud ? ", cloud" : "") + " FROM furniture_instances "; }

// The evidence of the map's pieces (of one piece when `instance_id` is given), into `records` by instance id.
void ReadEvidence(Connection& c, const std::string& map_id, std::optional<std::int64_t> instance_id,
                  std::vector<FurnitureInstanceRecord>& records) {
  std::map<std::int64_t, FurnitureInstanceRecord*> by_id;
  for (FurnitureInstanceRecord& r : records) by_id[r.instance_id] = &r;
  Statement s(c, std::string("SELECT e.instance_id, e.keyframe_id FROM furniture_instance_evidence e JOIN "
                             "furniture_instances f ON f.instance_id = e.instance_id WHERE f.map_id = ?") +
                     (instance_id ? " AND e.instance_id = ?" : "") + " ORDER BY e.instance_id, e.keyframe_id");
  s.Bind(1, map_id);
  if (instance_id) s.Bind(2, *instance_id);
  while (s.Step()) {
    if (const auto it = by_id.find(s.Int(0)); it != by_id.end()) it->second->evidence_keyframes.push_back(s.Int(1));
  }
}

}  // namespace

void UpsertFurnitureInstance(Connection& c, const FurnitureInstanceRecord& r) {
  Statement s(c,
              "INSERT INTO furniture_instances (instance_id, map_id, classifier, min_z_m, height_m, observations, "
              "job_id, cloud, created_ns, updated_ns) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?) "
              "ON CONFLICT (instance_id) DO UPDATE SET classifier = excluded.classifier, min_z_m = excluded.min_z_m, "
              "height_m = excluded.height_m, observations = excluded.observations, "
              "job_id = excluded.job_id, cloud = excluded.cloud, updated_ns = excluded.updated_ns");
  s.Bind(1, r.instance_id).Bind(2, r.map_id).Bind(3, r.classifier).Bind(4, r.min_z_m).Bind(5, r.height_m);
  s.Bind(6, r.observations);
  if (r.job_id) s.Bind(7, *r.job_id);
  else s.BindNull(7);
  s.BindBlob(8, r.cloud).Bind(9, r.created_ns).Bind(10, r.updated_ns);
  s.Step();
  Statement clear(c, "DELETE FROM furniture_instance_evidence WHERE instance_id = ?");
  clear.Bind(1, r.instance_id).Run();
  for (const std::int64_t keyframe : r.evidence_keyframes) {
    Statement(c, "INSERT INTO furniture_instance_evidence (instance_id, keyframe_id) VALUES (?, ?) ON CONFLICT DO NOTHING")
        .Bind(1, r.instance_id).Bind(2, keyframe).Run();
  }
}

std::optional<FurnitureInstanceRecord> FindFurnitureInstance(Connection& c, const std::string& map_id,
                                                             std::int64_t instance_id, bool with_cloud) {
  Statement s(c, Select(with_cloud) + "WHERE map_id = ? AND instance_id = ?");
  s.Bind(1, map_id).Bind(2, instance_id);
  if (!s.Step()) return std::nullopt;
  std::vector<FurnitureInstanceRecord> one{Row(s, with_cloud)};
  ReadEvidence(c, map_id, instance_id, one);
  return std::move(one.front());
}

std::vector<FurnitureInstanceRecord> ListFurnitureInstances(Connection& c, const std::string& map_id, bool with_cloud) {
  Statement s(c, Select(with_cloud) + "WHERE map_id = ? ORDER BY instance_id");
  s.Bind(1, map_id);
  std::vector<FurnitureInstanceRecord> out;
  while (s.Step()) out.push_back(Row(s, with_cloud));
  ReadEvidence(c, map_id, std::nullopt, out);
  return out;
}

}  // namespace anchordb::storage

namespace anchordb::storage {
std::vector<std::int64_t> NewestKeyframeIds(Connection& c, const std::string& map_id, int limit) {
  Statement s(c, "SELECT id FROM keyframes WHERE map_id = ? ORDER BY id DESC LIMIT ?");
  s.Bind(1, map_id).Bind(2, static_cast<std::int64_t>(limit));
  std::vector<std::int64_t> out;
  while (s.Step()) out.push_back(s.Int(0));
  return out;
}
}  // namespace anchordb::storage
