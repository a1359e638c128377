// Stored formats of the event layer and the typed views of its records (see event_records_internal.h).
#include "services/events/event_records_internal.h"

#include <algorithm>
#include <cstring>
#include <tuple>

#include "engine/classification/object_labels.h"
#include "schema/error.h"
#include "storage/blob_codec.h"
#include "storage/repositories.h"

namespace anchordb::services::events_internal {

namespace {

template <typename T>
std::vector<T> DecodeArray(const std::string& blob, storage::BlobElement element, std::size_t count) {
  auto out = storage::DecodeArray<T>(blob, element, count);
  if (!out) throw Error(ErrorCode::kInternal, "stored array does not match the camera");
  return std::move(*out);
}

}  // namespace

std::string EncodePoints(const std::vector<Eigen::Vector3f>& points) {
  std::vector<float> flat;
  flat.reserve(points.size() * 3);
  for (const auto& p : points) flat.insert(flat.end(), {p.x(), p.y(), p.z()});
  return storage::EncodeBlob(storage::BlobElement::kF32, {static_cast<std::uint32_t>(points.size()), 3}, storage::AsBytes(flat), 1);
}

std::vector<Eigen::Vector3f> DecodePoints(const std::string& blob) {
  std::vector<Eigen::Vector3f> out;
  if (blob.empty()) return out;
  const std::vector<float> flat = DecodeF32(blob);
  for (std::size_t i = 0; i + 2 < flat.size(); i += 3) out.emplace_back(flat[i], flat[i + 1], flat[i + 2]);
  return out;
}

std::vector<std::uint16_t> DecodeDepthMm(const std::string& blob, std::size_t count) { return DecodeArray<std::uint16_t>(blob, storage::BlobElement::kU16, count); }
std::vector<float> DecodeF32(const std::string& blob) { return DecodeArray<float>(blob, storage::BlobElement::kF32, 0); }

EventView ToView(const storage::EventRecord& e) {
  EventView v;
  v.id = e.id;
  v.type = e.type;
  v.detection = e.detection;
  v.stamp_ns = e.stamp_ns;
  v.scene_id = e.scene_id;
  v.action_layer = e.action_layer;
  v.instance_id = e.instance_id;
  v.segment_id = e.segment_id;
  v.label = e.label;
  v.explanation = e.explanation;
  v.details = EventDetailsOf(e.details);
  for (const auto& k : e.evidence) v.evidence.push_back({k.keyframe_id, k.role});
  return v;
}

InstanceView ToView(const storage::InstanceRecord& r) { return ToView(r, std::nullopt); }

engine::LabelWeights DecodeDistribution(const storage::InstanceClassificationRecord& r) {
  return r.distribution;
}

InstanceView ViewOf(storage::Connection& c, const storage::InstanceRecord& r) {
  return ToView(r, storage::FindInstanceClassification(c, r.map_id, r.id));
}

InstanceView ToView(const storage::InstanceRecord& r, const std::optional<storage::InstanceClassificationRecord>& classification) {
  InstanceView v;
  v.id = r.id;
  v.kind = r.kind;
  v.status = r.status;
  std::optional<engine::LabelWeights> classified;
  if (classification) {
    classified = DecodeDistribution(*classification);
    v.classification = ObjectClassificationView{classification->classifier, classification->label, *classified,
                                                classification->segment_id, classification->keyframe_id,
                                                classification->stamp_ns};
  }
  const engine::EffectiveLabels labels = engine::EffectiveObjectLabels(r.labels, r.label_locked, classified);
  v.labels = labels.distribution;
  v.label_source = engine::LabelSourceName(labels.source);
  v.label_locked = r.label_locked;
  v.pinned = r.pinned;
  v.position_m = Vec(r.position);
  v.extent_m = Vec(r.extent);
  v.yaw_rad = r.yaw_rad;
  v.last_seen_ns = r.last_seen_ns;
  v.last_scene_id = r.last_scene_id;
  v.created_ns = r.created_ns;
  v.updated_ns = r.updated_ns;
  return v;
}


storage::InstanceRecord RequireInstance(storage::Connection& c, const std::string& map, std::int64_t id) {
  RequireMap(c, map);
  auto r = storage::FindInstance(c, map, id, false);
  if (!r) throw Error(ErrorCode::kNotFound, "instance " + std::to_string(id) + " does not exist in map '" + map + "'", "instance");
  return *r;
}

bool SameRecord(const storage::InstanceRecord& a, const storage::InstanceRecord& b) {
  const auto columns = [](const storage::InstanceRecord& r) {
    return std::tie(r.id, r.map_id, r.kind, r.status, r.labels, r.label_locked, r.status_locked, r.pinned, r.yaw_rad,
                    r.sample, r.last_seen_ns, r.last_scene_id, r.created_ns, r.updated_ns);
  };
  return columns(a) == columns(b) && std::equal(a.position, a.position + 3, b.position) &&
         std::equal(a.extent, a.extent + 3, b.extent);
}

bool SameRecord(const storage::HistoryRecord& a, const storage::HistoryRecord& b) {
  return std::tie(a.instance_id, a.seq, a.stamp_ns, a.present, a.event_id) ==
             std::tie(b.instance_id, b.seq, b.stamp_ns, b.present, b.event_id) &&
         std::equal(a.position, a.position + 3, b.position);
}

}  // namespace anchordb::services::events_internal
