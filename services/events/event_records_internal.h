#pragma once
// Internal to services/events: the stored formats of the event layer (labels, details, point samples, arrays) and
// the conversion of stored records into the typed views the service returns.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/events/change_set.h"
#include "schema/types.h"
#include "services/events/event_details.h"
#include "services/events/event_types.h"
#include "storage/event_repository.h"
#include "storage/instance_classification_repository.h"
#include "storage/connection.h"
#include "services/common/require.h"

namespace anchordb::services::events_internal {

// A point sample (blob f32 {n, 3}); empty blob: no points.
std::string EncodePoints(const std::vector<Eigen::Vector3f>& points_m);
std::vector<Eigen::Vector3f> DecodePoints(const std::string& blob);
// A stored array as `T`s; `count` > 0 insists on that many (the model's camera). Throws Error(kInternal) otherwise.
std::vector<std::uint16_t> DecodeDepthMm(const std::string& blob, std::size_t count = 0);
std::vector<float> DecodeF32(const std::string& blob);
// A scene's stored intrinsics document.

inline Eigen::Vector3d Vec(const double* v) { return {v[0], v[1], v[2]}; }

EventView ToView(const storage::EventRecord& e);
InstanceView ToView(const storage::InstanceRecord& r);
// With the instance's classification: the classifier's distribution is the view's labels when nobody named it.
InstanceView ToView(const storage::InstanceRecord& r, const std::optional<storage::InstanceClassificationRecord>& classification);
// The view of an instance as stored, with its classification read on `c`.
InstanceView ViewOf(storage::Connection& c, const storage::InstanceRecord& r);
// A stored classification's distribution.
engine::LabelWeights DecodeDistribution(const storage::InstanceClassificationRecord& r);

// Throws Error(kNotFound, field "map") when the map does not exist.
using services::RequireMap;
// The instance (without its sample); Error(kNotFound) for a missing map or instance.
storage::InstanceRecord RequireInstance(storage::Connection& c, const std::string& map, std::int64_t id);

// Whether two reads of an instance (or a history row) agree in every column.
bool SameRecord(const storage::InstanceRecord& a, const storage::InstanceRecord& b);
bool SameRecord(const storage::HistoryRecord& a, const storage::HistoryRecord& b);

}  // namespace anchordb::services::events_internal
