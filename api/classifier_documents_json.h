#pragma once
// JSON of a classifier's stored documents (storage/classifier_documents.h, through the service's types): its options
// and report (GET /v1/classifiers) and the classifier_train job's request and result (GET /v1/jobs).
#include "schema/json_io.h"
#include "services/classification/classifier_types.h"

namespace anchordb::api {

// {"name", "base": [{"kind", and the kind's parameters}], "rounds", "selection", "sample_factor", "folds", "seed",
// "update", "error_on", "learning_rate", "unknown", "unknown_min_share"}
json::Json ToJson(const storage::ClassifierOptionsRecord& options);
// {"classes", "feature_types", "samples", "rounds": [{"setting", "feature_type", "error", "alpha"}], "train_seconds",
// "cross_validation"?: {"folds", "test_error", "train_error_per_round", "test_error_per_round",
// "test_error_worst_fold_per_round", "confusion", "rounds_per_fold", "kind_share", "setting_share", "feature_share"}}
json::Json ToJson(const storage::ClassifierReportRecord& report);
// The options and {"sample_count", "class_counts": {class: n}, "feature_dims": {type: d}, "staging"}.
json::Json ToJson(const storage::ClassifierTrainingRequestRecord& request);
// {"name", "rounds", "train_seconds", "test_error"?}
json::Json ToJson(const storage::ClassifierTrainingResultRecord& result);

// The writers of the classifier_train job's documents (api/job_json.h).
void RegisterClassifierJobDocumentWriters();

}  // namespace anchordb::api
