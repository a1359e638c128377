#pragma once
// Trained E-SAMME classifiers (thesis 4.2; SPEC §4.6): training as a job ("classifier_train": cross-validation,
// then the final model on every sample; progress per fold and round; cancellable), stored in the classifiers table
// (the base models serialised by OpenCV) with their report, listed, and used for predictions. Models reload after a
// restart and predict exactly as before.
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "schema/clock.h"
#include "services/classification/classifier_types.h"
#include "services/classification/object_classification.h"
#include "services/features/feature_service.h"
#include "services/grid/grid_service.h"
#include "services/jobs/job_service.h"
#include "storage/store.h"

namespace anchordb::services {

class ClassifierService {
 public:
  // Registers the "classifier_train" job kind with `jobs`. `features` and `grid` serve ClassifyRooms.
  ClassifierService(storage::Store& store, JobService& jobs, FeatureService& features, GridService& grid,
                    const Clock& clock = SystemClock::Instance());

  // Validates everything before queueing: a bad name, no samples, an empty class name, samples without every feature
  // type or with descriptors of differing length, NaN, fewer than two classes, a class with one sample, folds outside
  // [2, samples] (or 0), absurd rounds or settings: Error naming the field; nothing is queued or stored.
  // The job's request document holds the options and the sample, class and feature-type counts, not the samples:
  // those wait in memory until the job runs (a job interrupted by a restart fails, as every job does).
  JobTicket SubmitTraining(TrainClassifierRequest request);
  std::vector<ClassifierView> List();
  // Unknown name: kNotFound.
  ClassifierView Get(const std::string& name);
  // Unknown name: kNotFound; a sample missing a type or with a descriptor of the wrong length: kInvalidArgument.
  std::vector<ClassPrediction> Predict(const std::string& name, const PredictRequest& request);
  // The category distribution of each region; with `into`, paints each region's most probable category into that
  // label layer. A classifier feature type without a codebook in the map, or whose codebook's word count differs
  // from the classifier's descriptor length: kUnprocessable naming "classifier"; no regions: kInvalidArgument.
  std::vector<RoomClassification> ClassifyRooms(const ClassifyRoomsRequest& request);
  // Classifies an object instance from its newest segment (services/classification/object_classification.cc): the
  // points of the segment's box in its keyframe's cloud (the segment's stored sample when that keyframe is gone) ->
  // the classifier's feature types extracted -> bags of words over the map's codebooks -> the class distribution,
  // stored as the instance's classification. It becomes the instance's label only when no dialog or operator label
  // exists. Errors, nothing stored: unknown map, instance or classifier kNotFound; an instance deleted by an operator
  // or without a segment (entered by hand, or its segments forgotten) kConflict ("instance"); a furniture instance,
  // too few points, a classifier feature type the server cannot extract (not fpfh, shot or spd), without a codebook
  // in the map or whose codebook's word count is not the classifier's descriptor length kUnprocessable.
  InstanceClassificationResult ClassifyInstance(const ClassifyInstanceRequest& request);

 private:
  std::shared_ptr<const engine::EsammeModel> Model(const std::string& name);

  storage::Store& store_;
  JobService& jobs_;
  FeatureService& features_;
  GridService& grid_;
  const Clock& clock_;
  std::mutex mutex_;
  std::map<std::string, std::pair<std::int64_t, std::shared_ptr<const engine::EsammeModel>>> cache_;  // by name
  struct Staged {
    std::vector<ClassifierSample> samples;
    std::int64_t job = 0;  // 0 until the job is queued
  };
  // The samples of queued jobs, shared with the job runner (which may outlive a call, not the JobService).
  struct StagingArea {
    std::mutex mutex;
    std::map<std::int64_t, Staged> staged;  // by staging number (in the job's request)
    std::int64_t next = 1;
  };
  std::shared_ptr<StagingArea> staging_ = std::make_shared<StagingArea>();
};

}  // namespace anchordb::services
