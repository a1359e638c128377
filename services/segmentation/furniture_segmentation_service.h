#pragma once
// Furniture the robot finds itself (thesis 5.3.1, issue 16): a room cloud (the map's keyframes merged in the map
// frame, the OctoMap's occupied voxel centres, or a PCD / PLY cloud the client sends) is segmented
// (engine/segmentation), every segment classified (the named 3D shape model in verification mode, else the newest
// stored shape model, else by its gross shape alone,
// engine/segmentation/geometric_categories.h) and written as a furniture instance: a new one, or an update of the
// perceived piece its footprint overlaps (p(f) averaged over the observations, the newest geometry and cloud, the
// evidence keyframes joined). A piece an operator entered is never changed. The work runs as a job
// ("furniture_segment"); its result lists the segments.
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "schema/clock.h"
#include "services/common/exported_bytes.h"
#include "services/jobs/job_service.h"
#include "services/segmentation/segmentation_types.h"
#include "engine/cloud/cloud_io.h"
#include "storage/store.h"

namespace anchordb::engine {
struct ShapeModel;  // engine/shapes/shape_model.h (not included here: its engine::Detection meets the events' enum)
}

namespace anchordb::services {

// p(f) of a segment by a shape model in verification mode, as (category, probability) in the model's order
// (services/segmentation/shape_verification.cc; all zero when no ray voted).
std::vector<std::pair<std::string, double>> VerifySegment(const engine::ShapeModel& model, const std::vector<Eigen::Vector3f>& points_m);

// What segmentation reads from other capabilities (composed in services/common/capabilities.cc). Each may be empty:
// then that source or model is not available.
struct SegmentationLinks {
  // The stored shape model of a name (nullptr: no such model).
  std::function<std::shared_ptr<const engine::ShapeModel>(const std::string&)> shape_model;
  // The name of the newest stored shape model (nullopt: none is stored).
  std::function<std::optional<std::string>()> newest_shape_model;
  // The map's OctoMap as occupied voxel centres (nullopt: the map has no tree).
  std::function<std::optional<OccupiedCloud>(const std::string& map)> octomap;
};

// The segmentation capability's settings (services/segmentation/segmentation_settings.h binds them).
struct SegmentationSettings {
  std::size_t max_cloud_points = 4'000'000;  // a client's room cloud, and an OctoMap's occupied leaves: more is 413
};

class FurnitureSegmentationService {
 public:
  // `category_ids`: the grounding knowledge's categories (p(f) is over these).
  FurnitureSegmentationService(storage::Store& store, JobService& jobs, std::vector<std::string> category_ids,
                               const Clock& clock = SystemClock::Instance(), SegmentationLinks links = {},
                               SegmentationSettings settings = {});

  // Checks the request (Error naming "params.<name>", "keyframes", "max_range_m", "match_iou", "shape_model",
  // "source"; for the cloud source "body": bytes that do not decode 400, an empty cloud or NaN points 422, more than
  // settings' max_cloud_points 413) and queues the job. Unknown map kNotFound.
  JobTicket Submit(const std::string& map, const SegmentationRequest& request);
  // What the job does, run here and now (tests, evaluations, benchmarks).
  SegmentationOutcome Run(const std::string& map, const SegmentationRequest& request,
                          std::optional<std::int64_t> job_id = std::nullopt);

  // The furniture instances of the map (perceived and entered), by id.
  std::vector<FurnitureInstanceView> List(const std::string& map);
  FurnitureInstanceView Get(const std::string& map, std::int64_t id);  // kNotFound field "furniture"
  // The stored cloud of a perceived piece; an operator's piece has none (kUnprocessable).
  ExportedLayer Cloud(const std::string& map, std::int64_t id, engine::CloudFormat format);

  // Room clouds of submitted cloud-source jobs, waiting in memory for their job (by staging number).
  struct CloudStaging {
    std::mutex mutex;
    std::map<std::int64_t, std::vector<Eigen::Vector3f>> clouds;
    std::int64_t next = 1;
  };
  // What a run needs, shared with the job's runner (which may outlive this object while the job service stops).
  struct Core {
    storage::Store& store;
    std::vector<std::string> category_ids;
    const Clock& clock;
    SegmentationLinks links;
    SegmentationSettings settings;
    std::shared_ptr<CloudStaging> staging = std::make_shared<CloudStaging>();
  };

 private:
  storage::Store& store_;
  JobService& jobs_;
  std::shared_ptr<Core> core_;
};

// The request as the job stores it, and back (services/segmentation/segmentation_request.cc); the cloud source's
// points are not in it, only their `staging` number.
std::string SegmentationRequestDocument(const SegmentationRequest& r, std::optional<std::int64_t> staging = std::nullopt);
SegmentationRequest SegmentationRequestFromDocument(const std::string& text, std::optional<std::int64_t>* staging = nullptr);
// The job's result document (the job status shows it; each segment names its cloud's route under `map`).
std::string SegmentationResultDocument(const SegmentationOutcome& out, const std::string& map);
// The decoded room cloud of the cloud source, of at most `max_points` points (Error field "body" as Submit says).
std::vector<Eigen::Vector3f> DecodeRoomCloud(const std::string& bytes, bool skip_nonfinite, std::size_t max_points);
// Throws Error naming the field for a value out of range.
void CheckSegmentationRequest(const SegmentationRequest& r);

}  // namespace anchordb::services
