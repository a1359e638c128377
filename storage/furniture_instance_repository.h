#pragma once
// SQL for perceived furniture (migration 0014): the perception record beside a furniture instance's row in
// `instances` (storage/event_repository.h), with the keyframes that saw it (furniture_instance_evidence, 0025).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "storage/connection.h"

namespace anchordb::storage {

struct FurnitureInstanceRecord {
  std::int64_t instance_id = 0;
  std::string map_id;
  std::string classifier;
  double min_z_m = 0.0, height_m = 0.0;
  std::int64_t observations = 1;
  std::vector<std::int64_t> evidence_keyframes;  // ascending, each once
  std::optional<std::int64_t> job_id;
  std::string cloud;  // blob f32 {n, 3}; empty when read without it
  std::int64_t created_ns = 0, updated_ns = 0;
};

// By instance_id; the evidence rows are replaced by the record's.
void UpsertFurnitureInstance(Connection& c, const FurnitureInstanceRecord& r);
std::optional<FurnitureInstanceRecord> FindFurnitureInstance(Connection& c, const std::string& map_id,
                                                             std::int64_t instance_id, bool with_cloud);
std::vector<FurnitureInstanceRecord> ListFurnitureInstances(Connection& c, const std::string& map_id, bool with_cloud);

}  // namespace anchordb::storage

namespace anchordb::storage {
// Ids of the map's keyframes, newest first, at most `limit` (the room cloud of a segmentation).
std::vector<std::int64_t> NewestKeyframeIds(Connection& c, const std::string& map_id, int limit);
}  // namespace anchordb::storage
