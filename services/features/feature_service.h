#pragma once
// Anchored features (SPEC §4.6, thesis 4.3.2): client batches de-duplicated on insert (close in descriptor space and
// in 3D, thresholds per type), spatial and time queries through the R*Tree, codebooks per type by k-means as a job
// ("codebook"; every feature of the type gets its codeword, later ones on insert) and bags of words of a region.
#include <string>

#include "schema/clock.h"
#include "services/features/feature_types.h"
#include "services/jobs/job_service.h"
#include "storage/store.h"

namespace anchordb::services {

class FeatureService {
 public:
  // Registers the "codebook" job kind with `jobs`. `store`, `jobs` and `clock` must outlive the service.
  FeatureService(storage::Store& store, JobService& jobs, FeatureSettings settings = {},
                 const Clock& clock = SystemClock::Instance());

  // Validates the whole batch first (unknown type, wrong descriptor length, NaN/inf, unknown keyframe, too many:
  // Error naming the field; nothing is stored), then inserts it in one transaction. Unknown map: kNotFound.
  FeatureBatchResult AddBatch(const std::string& map, const FeatureBatch& batch);
  // kInvalidArgument for a limit outside [1, 10000], a negative radius, an inverted box or time range.
  FeaturePage List(const std::string& map, const FeatureQuery& query);
  // Queues a codebook job; bad type or words: kInvalidArgument; fewer stored features than words: kUnprocessable.
  JobTicket SubmitCodebook(const std::string& map, const CodebookRequest& request);
  // kNotFound when the type has no codebook.
  CodebookView GetCodebook(const std::string& map, const std::string& type);
  // kNotFound without a codebook; kInvalidArgument unless exactly one of sphere, box, polygon is given.
  BowResult BagOfWords(const std::string& map, const BowQuery& query);

  // Extracts features from a keyframe's cloud (its raw depth back-projected with its model's camera into the map
  // frame) outside the write lock, then stores them as batches with the keyframe's id and stamp (de-duplicated).
  // Unknown keyframe: kNotFound; a type outside fpfh, shot, spd: kInvalidArgument ("types").
  ExtractResult ExtractKeyframe(const std::string& map, std::int64_t keyframe, const ExtractRequest& request);

  const FeatureSettings& settings() const { return settings_; }

 private:
  const engine::DedupThreshold& ThresholdOf(const std::string& type) const;

  storage::Store& store_;
  JobService& jobs_;
  FeatureSettings settings_;
  const Clock& clock_;
};

}  // namespace anchordb::services
