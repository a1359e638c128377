#pragma once
// Trained 3D shape models (thesis 4.1; SPEC §4.7): training as a job ("shape_model_train": virtual scans of the
// meshes, features, codebook, vote histograms; progress per stage; cancellable), stored in the shape_models table
// with the training report, listed, and used for verification (one sphere at a segment's centre -> p(f)) and
// detection. Models reload after a restart and predict exactly as before (the blob holds every parameter).
//
// The decoded training samples wait in memory for their job (a request of many clouds is not copied into the jobs
// table, which keeps the options and a summary of the parts); a job interrupted by a server stop is failed at start-up
// like every other job, and its samples are gone with the process.
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "engine/shapes/virtual_scan.h"
#include "schema/clock.h"
#include "services/jobs/job_service.h"
#include "services/shapes/shape_types.h"
#include "storage/store.h"

namespace anchordb::services {

struct ShapeSettings {
  std::size_t max_points = 2000000;     // per cloud (training part or query): more is kPayloadTooLarge
  std::size_t max_samples = 5000;       // training parts per request
};

class ShapeService {
 public:
  // Registers the "shape_model_train" job kind with `jobs`.
  ShapeService(storage::Store& store, JobService& jobs, ShapeSettings settings = {},
               const Clock& clock = SystemClock::Instance());

  // Decodes and checks every part before queueing: a bad name, no samples, an empty category, a cloud that does not
  // decode (400) or is empty / has non-finite points (422), a mesh with broken faces (422), a listed category
  // without samples (422), parameters out of range (400): Error naming the field; nothing is queued or stored.
  JobTicket SubmitTraining(const TrainShapeModelRequest& request);
  std::vector<ShapeModelView> List();
  // Unknown name: kNotFound.
  ShapeModelView Get(const std::string& name);
  void Delete(const std::string& name);
  // `body`: PCD or PLY. Unknown model: kNotFound; bytes that do not decode: kInvalidArgument ("body"); an empty
  // cloud or non-finite points: kUnprocessable ("body").
  ShapeClassification Classify(const std::string& name, const std::string& body);
  ShapeDetections Detect(const std::string& name, const std::string& body);
  // The decoded stored model of a name (cached while its row is unchanged); nullptr when there is none.
  std::shared_ptr<const engine::ShapeModel> Find(const std::string& name);
  // The name of the most recently trained stored model; nullopt when none is stored.
  std::optional<std::string> Newest();

 private:
  std::shared_ptr<const engine::ShapeModel> Model(const std::string& name);
  std::vector<Eigen::Vector3f> DecodeQuery(const std::string& body) const;

  storage::Store& store_;
  JobService& jobs_;
  ShapeSettings settings_;
  const Clock& clock_;
  std::mutex mutex_;
  std::map<std::string, std::pair<std::int64_t, std::shared_ptr<const engine::ShapeModel>>> cache_;  // by name
  struct Staged {
    std::vector<engine::LabelledCloud> clouds;
    std::vector<std::pair<std::string, engine::TriangleMesh>> meshes;  // category, mesh
    int mesh_views = 12;
  };
  // Shared with the job runner (which may outlive a call, not the JobService).
  struct StagingArea {
    std::mutex mutex;
    std::map<std::int64_t, Staged> staged;  // by staging number (in the job's request)
    std::int64_t next = 1;
  };
  std::shared_ptr<StagingArea> staging_ = std::make_shared<StagingArea>();
};

}  // namespace anchordb::services
