#include "storage/octomap_repository.h"

#include "schema/error.h"
#include "storage/blob_codec.h"

namespace anchordb::storage {

namespace {

constexpr const char* kOctomapColumns =
    "map_id, format, version, resolution_m, prob_hit, prob_miss, clamp_min, clamp_max, occupancy_threshold, "
    "max_range_m, base_stamp_ns, leaves, occupied_leaves, created_ns, updated_ns, length(tree), length(stamps), "
    "keyframes_through, events_through";

OctomapRecord Row(const Statement& s) {
  OctomapRecord r;
  r.map_id = s.Text(0);
  r.format = s.Int(1);
  r.version = s.Int(2);
  r.resolution_m = s.Double(3);
  r.prob_hit = s.Double(4);
  r.prob_miss = s.Double(5);
  r.clamp_min = s.Double(6);
  r.clamp_max = s.Double(7);
  r.occupancy_threshold = s.Double(8);
  r.max_range_m = s.Double(9);
  r.base_stamp_ns = s.Int(10);
  r.leaves = s.Int(11);
  r.occupied_leaves = s.Int(12);
  r.created_ns = s.Int(13);
  r.updated_ns = s.Int(14);
  r.tree_bytes = s.Int(15);
  r.stamps_bytes = s.Int(16);
  r.keyframes_through = s.Int(17);
  r.events_through = s.Int(18);
  return r;
}

}  // namespace

std::optional<OctomapRecord> FindOctomap(Connection& c, const std::string& map_id, bool with_blobs) {
  Statement s(c, std::string("SELECT ") + kOctomapColumns + (with_blobs ? ", tree, stamps" : "") +
                     " FROM octomaps WHERE map_id = ?");
  s.Bind(1, map_id);
  if (!s.Step()) return std::nullopt;
  OctomapRecord r = Row(s);
  if (with_blobs) {
    r.tree_blob = s.Blob(19);
    r.stamps_blob = s.Blob(20);
  }
  return r;
}

std::int64_t UpsertOctomap(Connection& c, const OctomapRecord& r, std::optional<std::int64_t> expected_version) {
  const std::optional<OctomapRecord> stored = FindOctomap(c, r.map_id, false);
  const std::optional<std::int64_t> stored_version =
      stored ? std::optional<std::int64_t>(stored->version) : std::nullopt;
  if (stored_version != expected_version) {
    throw Error(ErrorCode::kConflict, "the octomap of map '" + r.map_id + "' changed meanwhile; retry", "map");
  }
  const std::int64_t version = stored ? stored->version + 1 : 1;
  Statement s(c,
              "INSERT INTO octomaps (map_id, format, version, resolution_m, prob_hit, prob_miss, clamp_min, clamp_max, "
              "occupancy_threshold, max_range_m, tree, stamps, base_stamp_ns, leaves, occupied_leaves, created_ns, "
              "updated_ns, keyframes_through, events_through) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?) "
              "ON CONFLICT (map_id) DO UPDATE SET format = excluded.format, version = excluded.version, "
              "resolution_m = excluded.resolution_m, prob_hit = excluded.prob_hit, prob_miss = excluded.prob_miss, "
              "clamp_min = excluded.clamp_min, clamp_max = excluded.clamp_max, "
              "occupancy_threshold = excluded.occupancy_threshold, max_range_m = excluded.max_range_m, "
              "tree = excluded.tree, stamps = excluded.stamps, base_stamp_ns = excluded.base_stamp_ns, "
              "leaves = excluded.leaves, occupied_leaves = excluded.occupied_leaves, updated_ns = excluded.updated_ns, "
              "keyframes_through = excluded.keyframes_through, events_through = excluded.events_through");
  s.Bind(1, r.map_id).Bind(2, r.format).Bind(3, version).Bind(4, r.resolution_m).Bind(5, r.prob_hit);
  s.Bind(6, r.prob_miss).Bind(7, r.clamp_min).Bind(8, r.clamp_max).Bind(9, r.occupancy_threshold);
  s.Bind(10, r.max_range_m).BindBlob(11, r.tree_blob).BindBlob(12, r.stamps_blob).Bind(13, r.base_stamp_ns);
  s.Bind(14, r.leaves).Bind(15, r.occupied_leaves).Bind(16, stored ? stored->created_ns : r.created_ns);
  s.Bind(17, r.updated_ns).Bind(18, r.keyframes_through).Bind(19, r.events_through).Run();
  return version;
}

bool DeleteOctomap(Connection& c, const std::string& map_id) {
  Statement s(c, "DELETE FROM octomaps WHERE map_id = ?");
  s.Bind(1, map_id).Run();
  return c.Changes() > 0;
}

std::vector<std::int64_t> KeyframeIdsAfter(Connection& c, const std::string& map_id, std::int64_t after_id, int limit) {
  Statement s(c, "SELECT id FROM keyframes WHERE map_id = ? AND id > ? ORDER BY id LIMIT ?");
  s.Bind(1, map_id).Bind(2, after_id).Bind(3, static_cast<std::int64_t>(limit));
  std::vector<std::int64_t> out;
  while (s.Step()) out.push_back(s.Int(0));
  return out;
}

std::vector<RemovedSegment> RemovedSegmentsAfter(Connection& c, const std::string& map_id, std::int64_t after_event_id,
                                                 int limit) {
  Statement s(c,
              "SELECT e.id, s.min_x_m, s.min_y_m, s.min_z_m, s.max_x_m, s.max_y_m, s.max_z_m FROM events e "
              "JOIN segments s ON s.id = e.segment_id WHERE e.map_id = ? AND e.id > ? AND e.type = 'removed' "
              "ORDER BY e.id LIMIT ?");
  s.Bind(1, map_id).Bind(2, after_event_id).Bind(3, static_cast<std::int64_t>(limit));
  std::vector<RemovedSegment> out;
  while (s.Step()) {
    RemovedSegment r;
    r.event_id = s.Int(0);
    for (int i = 0; i < 3; ++i) {
      r.min_m[i] = s.Double(1 + i);
      r.max_m[i] = s.Double(4 + i);
    }
    out.push_back(r);
  }
  return out;
}

std::int64_t LastEventId(Connection& c, const std::string& map_id) {
  Statement s(c, "SELECT COALESCE(MAX(id), 0) FROM events WHERE map_id = ?");
  s.Bind(1, map_id);
  return s.Step() ? s.Int(0) : 0;
}

std::string EncodeOctomapTree(std::string_view ot_stream) {
  return EncodeBlob(BlobElement::kU8, {static_cast<std::uint32_t>(ot_stream.size())}, ot_stream);
}

std::string DecodeOctomapTree(std::string_view blob, const std::string& map_id) {
  const DecodedBlob d = DecodeBlob(blob);
  if (d.element != BlobElement::kU8 || d.shape.size() != 1) {
    throw Error(ErrorCode::kInternal, "the stored octomap of map '" + map_id + "' is not a byte stream");
  }
  return d.bytes;
}

std::string EncodeOctomapStamps(const std::vector<std::pair<std::uint64_t, std::int64_t>>& stamps) {
  std::vector<std::uint32_t> rows;
  rows.reserve(stamps.size() * 4);
  for (const auto& [key, stamp] : stamps) {
    const auto s = static_cast<std::uint64_t>(stamp);
    rows.insert(rows.end(), {static_cast<std::uint32_t>(key), static_cast<std::uint32_t>(key >> 32),
                             static_cast<std::uint32_t>(s), static_cast<std::uint32_t>(s >> 32)});
  }
  return EncodeBlob(BlobElement::kU32, {static_cast<std::uint32_t>(stamps.size()), 4}, AsBytes(rows));
}

std::vector<std::pair<std::uint64_t, std::int64_t>> DecodeOctomapStamps(std::string_view blob, const std::string& map_id) {
  const std::optional<std::vector<std::uint32_t>> rows = DecodeArray<std::uint32_t>(blob, BlobElement::kU32);
  if (!rows || rows->size() % 4 != 0) {
    throw Error(ErrorCode::kInternal, "the stored octomap stamps of map '" + map_id + "' do not decode");
  }
  std::vector<std::pair<std::uint64_t, std::int64_t>> out(rows->size() / 4);
  for (std::size_t i = 0; i < out.size(); ++i) {
    const std::uint32_t* r = rows->data() + 4 * i;
    out[i] = {std::uint64_t{r[0]} | (std::uint64_t{r[1]} << 32),
              static_cast<std::int64_t>(std::uint64_t{r[2]} | (std::uint64_t{r[3]} << 32))};
  }
  return out;
}

}  // namespace anchordb::storage
