#pragma once
// SQL for object classifications (migration 0015): a classifier's class distribution per instance (its shares are
// rows of instance_classification_shares, migration 0026), and the segment an instance was last seen as (through its
// events).
#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "storage/event_repository.h"
#include "storage/connection.h"

namespace anchordb::storage {

struct InstanceClassificationRecord {
  std::int64_t instance_id = 0;
  std::string map_id;
  std::string classifier;
  std::string label;
  std::map<std::string, double> distribution;  // class -> share, every class of the classifier
  std::optional<std::int64_t> segment_id;
  std::optional<std::int64_t> keyframe_id;
  std::int64_t stamp_ns = 0;
};
// Inserts or replaces the instance's classification with its distribution.
void UpsertInstanceClassification(Connection& c, const InstanceClassificationRecord& r);
std::optional<InstanceClassificationRecord> FindInstanceClassification(Connection& c, const std::string& map_id,
                                                                       std::int64_t instance_id);

// The segment of the instance's newest event that has one (added, moved, removed, re-analysed: its points are the
// object as some keyframe saw it); nullopt when no event of the instance has a segment (entered by hand, or
// forgetting dropped them).
std::optional<SegmentRecord> LatestInstanceSegment(Connection& c, const std::string& map_id, std::int64_t instance_id);

}  // namespace anchordb::storage
