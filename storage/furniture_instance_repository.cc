#include "storage/furniture_instance_repository.h"

namespace anchordb::storage {
namespace {

constexpr const char* kFurnitureColumns =
    "instance_id, map_id, classifier, min_z_m, height_m, observations, evidence_json, job_id, created_ns, updated_ns";

FurnitureInstanceRecord Row(const Statement& s, bool with_cloud) {
  FurnitureInstanceRecord r;
  r.instance_id = s.Int(0);
  r.map_id = s.Text(1);
  r.classifier = s.Text(2);
  r.min_z_m = s.Double(3);
  r.height_m = s.Double(4);
  r.observations = s.Int(5);
  r.evidence_json = s.Text(6);
  if (!s.IsNull(7)) r.job_id = s.Int(7);
  r.created_ns = s.Int(8);
  r.updated_ns = s.Int(9);
  if (with_cloud) r.cloud = s.Blob(10);
  return r;
}

std::string Select(bool with_cloud) { return std::string("SELECT ") + kFurnitureColumns + (with_cloud ? ", cloud" : "") + " FROM furniture_instances "; }

}  // namespace

void UpsertFurnitureInstance(Connection& c, const FurnitureInstanceRecord& r) {
  Statement s(c,
              "INSERT INTO furniture_instances (instance_id, map_id, classifier, min_z_m, height_m, observations, "
              "evidence_json, job_id, cloud, created_ns, updated_ns) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?) "
              "ON CONFLICT (instance_id) DO UPDATE SET classifier = excluded.classifier, min_z_m = excluded.min_z_m, "
              "height_m = excluded.height_m, observations = excluded.observations, evidence_json = excluded.evidence_json, "
              "job_id = excluded.job_id, cloud = excluded.cloud, updated_ns = excluded.updated_ns");
  s.Bind(1, r.instance_id).Bind(2, r.map_id).Bind(3, r.classifier).Bind(4, r.min_z_m).Bind(5, r.height_m);
  s.Bind(6, r.observations).Bind(7, r.evidence_json);
  if (r.job_id) s.Bind(8, *r.job_id);
  else s.BindNull(8);
  s.BindBlob(9, r.cloud).Bind(10, r.created_ns).Bind(11, r.updated_ns);
  s.Step();
}

std::optional<FurnitureInstanceRecord> FindFurnitureInstance(Connection& c, const std::string& map_id,
                                                             std::int64_t instance_id, bool with_cloud) {
  Statement s(c, Select(with_cloud) + "WHERE map_id = ? AND instance_id = ?");
  s.Bind(1, map_id).Bind(2, instance_id);
  if (!s.Step()) return std::nullopt;
  return Row(s, with_cloud);
}

std::vector<FurnitureInstanceRecord> ListFurnitureInstances(Connection& c, const std::string& map_id, bool with_cloud) {
  Statement s(c, Select(with_cloud) + "WHERE map_id = ? ORDER BY instance_id");
  s.Bind(1, map_id);
  std::vector<FurnitureInstanceRecord> out;
  while (s.Step()) out.push_back(Row(s, with_cloud));
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
