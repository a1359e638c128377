#pragma once
// The per-map 3D occupancy tree row (migrations/0011_octomaps.sql) and the codecs of its two blobs: the .ot stream
// (u8, zstd) and the per-voxel stamps (u32 rows of 4: packed key low/high, stamp low/high). Decoding a blob that does
// not match throws Error(kInternal) naming the map, so a corrupt row is reported, never misread.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "storage/connection.h"

namespace anchordb::storage {

struct OctomapRecord {
  std::string map_id;
  std::int64_t format = 1;
  std::int64_t version = 0;  // assigned by UpsertOctomap
  double resolution_m = 0.05;
  double prob_hit = 0.7;
  double prob_miss = 0.4;
  double clamp_min = 0.12;
  double clamp_max = 0.97;
  double occupancy_threshold = 0.5;
  double max_range_m = 5.0;
  std::string tree_blob;    // empty when not loaded
  std::string stamps_blob;  // empty when not loaded
  std::int64_t base_stamp_ns = 0;
  std::int64_t leaves = 0;
  std::int64_t occupied_leaves = 0;
  std::int64_t keyframes_through = 0;  // keyframes with id <= this are integrated (octomap_from_keyframes)
  std::int64_t events_through = 0;     // removal events with id <= this had their voxels cleared
  std::int64_t created_ns = 0;
  std::int64_t updated_ns = 0;
  std::int64_t tree_bytes = 0;    // stored sizes of the blobs
  std::int64_t stamps_bytes = 0;
};

std::optional<OctomapRecord> FindOctomap(Connection& c, const std::string& map_id, bool with_blobs);
// Inserts the row, or replaces it when `expected_version` is the stored version (kConflict otherwise; nullopt
// expects no row). Returns the new version.
std::int64_t UpsertOctomap(Connection& c, const OctomapRecord& record, std::optional<std::int64_t> expected_version);
bool DeleteOctomap(Connection& c, const std::string& map_id);

// Keyframe ids of the map after `after_id`, ascending, at most `limit`.
std::vector<std::int64_t> KeyframeIdsAfter(Connection& c, const std::string& map_id, std::int64_t after_id, int limit);

// A 'removed' change event with its segment's box in the map frame [m].
struct RemovedSegment {
  std::int64_t event_id = 0;
  double min_m[3] = {0, 0, 0};
  double max_m[3] = {0, 0, 0};
};
// The map's 'removed' events with a segment after `after_event_id`, ascending, at most `limit`; and the largest event
// id of the map (0 without events).
std::vector<RemovedSegment> RemovedSegmentsAfter(Connection& c, const std::string& map_id, std::int64_t after_event_id,
                                                 int limit);
std::int64_t LastEventId(Connection& c, const std::string& map_id);

std::string EncodeOctomapTree(std::string_view ot_stream);
std::string DecodeOctomapTree(std::string_view blob, const std::string& map_id);
std::string EncodeOctomapStamps(const std::vector<std::pair<std::uint64_t, std::int64_t>>& stamps);
std::vector<std::pair<std::uint64_t, std::int64_t>> DecodeOctomapStamps(std::string_view blob, const std::string& map_id);

}  // namespace anchordb::storage
