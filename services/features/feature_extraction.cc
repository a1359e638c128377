// FeatureService::ExtractKeyframe: PCL extraction (engine/features/extraction.h) from a stored keyframe.
#include <chrono>

#include "engine/scene/projection.h"
#include "schema/error.h"
#include "services/common/require.h"
#include "services/features/feature_service.h"
#include "services/scene/keyframe_listener.h"

namespace anchordb::services {

ExtractResult FeatureService::ExtractKeyframe(const std::string& map, std::int64_t keyframe, const ExtractRequest& request) {
  if (request.types.empty()) throw Error(ErrorCode::kInvalidArgument, "types must name at least one type", "types");
  for (const auto& t : request.types) {
    if (t != "fpfh" && t != "shot" && t != "spd") {
      throw Error(ErrorCode::kInvalidArgument, "the server extracts fpfh, shot and spd, not '" + t.substr(0, 40) + "'", "types");
    }
  }
  const auto notice = store_.Read([&](storage::Connection& c) {
    RequireMap(c, map);
    return LoadKeyframeNotice(c, map, keyframe);
  });
  if (!notice) throw Error(ErrorCode::kNotFound, "keyframe " + std::to_string(keyframe) + " does not exist", "keyframe");
  const auto cloud_m = engine::BackProjectRaw(notice->depth_mm, 1000.0, notice->K, notice->X_MapCamera);
  const auto start = std::chrono::steady_clock::now();
  const auto extracted = engine::ExtractFeatures(cloud_m, notice->X_MapCamera.translation(), request.types,
                                                 settings_.extraction);
  ExtractResult result;
  result.keyframe = keyframe;
  result.points = static_cast<int>(cloud_m.size());
  result.extract_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (const auto& type : request.types) {
    FeatureBatch batch;
    batch.type = type;
    batch.stamp_ns = notice->stamp_ns;
    for (const auto& f : extracted) {
      if (f.type == type) batch.features.push_back({f.descriptor, f.anchor_m, keyframe});
    }
    ExtractResult::PerType counts;
    counts.type = type;
    counts.extracted = static_cast<int>(batch.features.size());
    // A keyframe gives at most a few thousand features per type; batches larger than the client limit are split.
    for (std::size_t at = 0; at < batch.features.size(); at += static_cast<std::size_t>(settings_.max_batch)) {
      FeatureBatch part;
      part.type = type;
      part.stamp_ns = batch.stamp_ns;
      const std::size_t end = std::min(batch.features.size(), at + static_cast<std::size_t>(settings_.max_batch));
      part.features.assign(batch.features.begin() + static_cast<std::ptrdiff_t>(at), batch.features.begin() + static_cast<std::ptrdiff_t>(end));
      const FeatureBatchResult r = AddBatch(map, part);
      counts.inserted += r.inserted;
      counts.duplicates += r.duplicates;
    }
    result.types.push_back(counts);
  }
  return result;
}

}  // namespace anchordb::services
