// Point clouds out of the memory (SPEC 4.9): keyframes and event segments as PCD / PLY.
#include "engine/scene/projection.h"
#include "schema/error.h"
#include "services/common/cloud_bytes.h"
#include "services/common/require.h"
#include "services/octomap/octomap_service.h"
#include "services/scene/keyframe_listener.h"
#include "storage/blob_codec.h"
#include "storage/event_repository.h"

namespace anchordb::services {

ExportedLayer OctomapService::KeyframeCloud(const std::string& map, std::int64_t keyframe_id, bool background,
                                            bool map_frame, engine::CloudFormat format) {
  const std::optional<KeyframeNotice> kf = store_.Read([&](storage::Connection& c) {
    RequireMap(c, map);
    return LoadKeyframeNotice(c, map, keyframe_id);
  });
  if (!kf) {
    throw Error(ErrorCode::kNotFound, "keyframe " + std::to_string(keyframe_id) + " does not exist in map '" + map + "'",
                "keyframe");
  }
  const Eigen::Isometry3d X = map_frame ? kf->X_MapCamera : Eigen::Isometry3d::Identity();
  ExportedLayer out = CloudBytes(engine::BackProjectRaw(background ? kf->background_mm : kf->depth_mm, 1000.0, kf->K, X),
                               format);
  out.frame = map_frame ? CoordinateFrame::kMap : CoordinateFrame::kCamera;
  return out;
}

ExportedLayer OctomapService::EventSegmentCloud(const std::string& map, std::int64_t event_id,
                                                engine::CloudFormat format) {
  const std::string sample = store_.Read([&](storage::Connection& c) {
    RequireMap(c, map);
    const std::optional<storage::EventRecord> e = storage::FindEvent(c, map, event_id);
    if (!e) {
      throw Error(ErrorCode::kNotFound, "event " + std::to_string(event_id) + " does not exist in map '" + map + "'",
                  "event");
    }
    if (!e->segment_id) throw Error(ErrorCode::kUnprocessable, "event " + std::to_string(event_id) + " has no segment", "event");
    const std::optional<storage::SegmentRecord> s = storage::FindSegment(c, *e->segment_id);
    if (!s) throw Error(ErrorCode::kUnprocessable, "the segment of event " + std::to_string(event_id) + " is gone", "event");
    return s->sample;
  });
  std::vector<Eigen::Vector3f> points;
  if (!sample.empty()) {
    const std::optional<std::vector<float>> xyz = storage::DecodeArray<float>(sample, storage::BlobElement::kF32);
    if (!xyz || xyz->size() % 3 != 0) throw Error(ErrorCode::kInternal, "a stored segment sample does not decode");
    for (std::size_t i = 0; i + 2 < xyz->size(); i += 3) points.emplace_back((*xyz)[i], (*xyz)[i + 1], (*xyz)[i + 2]);
  }
  return CloudBytes(points, format);
}

}  // namespace anchordb::services
