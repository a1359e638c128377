#pragma once
// JSON of trained classifiers (SPEC §5: POST /v1/classifiers, GET /v1/classifiers[/{name}], :predict).
#include "api/http_api.h"
#include "services/classification/classifier_types.h"

namespace anchordb::api {

// {"name", "samples": [{"label", "features": {"<type>": [...]}}], "base"?: [{"kind": "svm", "C": 1 | [..],
// "gamma": 0.1 | [..]} | {"kind": "dtree", "max_depth", "min_samples"} | {"kind": "mlp", "hidden": [..],
// "iterations"} | {"kind": "knn", "k"}], "rounds", "selection", "sample_factor", "folds", "seed",
// "update": "thesis|sklearn", "unknown", "unknown_min_share"}
services::TrainClassifierRequest ParseTrainClassifierRequest(const Json& body);
Json ToJson(const services::ClassifierView& v);
// {"samples": [{"features": {...}}], "rounds"?}
services::PredictRequest ParsePredictRequest(const Json& body);
Json ToJson(const std::vector<services::ClassPrediction>& predictions);

// {"classifier", "regions": [{"id"?, "polygon": [[x, y], ...]}], "into"?}
services::ClassifyRoomsRequest ParseClassifyRoomsRequest(const std::string& map, const Json& body);
Json ToJson(const std::vector<services::RoomClassification>& rooms);

}  // namespace anchordb::api
