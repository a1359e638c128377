// ClassifierService::ClassifyInstance: object classification from an instance's segment (see classifier_service.h).
#include <algorithm>
#include <numeric>

#include "engine/classification/object_labels.h"
#include "engine/events/sentences.h"
#include "engine/features/extraction.h"
#include "engine/features/features.h"
#include "engine/scene/projection.h"
#include "schema/error.h"
#include "schema/ids.h"
#include "services/classification/classifier_service.h"
#include "services/common/require.h"
#include "services/events/event_details.h"
#include "services/scene/keyframe_listener.h"
#include "storage/blob_codec.h"
#include "storage/feature_repository.h"
#include "storage/instance_classification_repository.h"

namespace anchordb::services {
namespace {

// The segment's box grows by this much before its keyframe's points are taken [m]: depth noise at its border.
constexpr double kSegmentMarginM = 0.01;

bool ServerExtracts(const std::string& type) { return type == "fpfh" || type == "shot" || type == "spd"; }

std::vector<Eigen::Vector3f> SamplePoints(const std::string& blob) {
  std::vector<Eigen::Vector3f> out;
  if (blob.empty()) return out;
  const auto flat = storage::DecodeArray<float>(blob, storage::BlobElement::kF32);
  if (!flat) return out;
  for (std::size_t i = 0; i + 2 < flat->size(); i += 3) out.emplace_back((*flat)[i], (*flat)[i + 1], (*flat)[i + 2]);
  return out;
}

std::string NotFound(const std::string& what, std::int64_t id, const std::string& map) {
  return what + " " + std::to_string(id) + " does not exist in map '" + map + "'";
}

// Throws unless the instance may be classified (it exists, is an object, was not deleted by an operator).
const storage::InstanceRecord& RequireClassifiable(const std::optional<storage::InstanceRecord>& r,
                                                   const ClassifyInstanceRequest& request) {
  if (!r) throw Error(ErrorCode::kNotFound, NotFound("instance", request.instance, request.map), "instance");
  if (r->status == "deleted") {
    throw Error(ErrorCode::kConflict, "instance " + std::to_string(request.instance) + " was deleted by an operator", "instance");
  }
  if (r->kind != "object") {
    throw Error(ErrorCode::kUnprocessable, "instance " + std::to_string(request.instance) +
                                               " is furniture; object classification classifies objects", "instance");
  }
  return *r;
}

void CheckClassifyRequest(const ClassifyInstanceRequest& request) {
  json::CheckId(request.classifier, "classifier");
  if (!(request.keypoint_spacing_m >= 0.005 && request.keypoint_spacing_m <= 0.5)) {
    throw Error(ErrorCode::kInvalidArgument, "keypoint_spacing_m must lie in [0.005, 0.5] m", "keypoint_spacing_m");
  }
  if (request.min_points < 10 || request.min_points > 1000000) {
    throw Error(ErrorCode::kInvalidArgument, "min_points must lie in [10, 1000000]", "min_points");
  }
}

// What a classification reads: the instance's newest segment, its keyframe (when kept) and the map's codebook of
// each of the classifier's feature types (checked against the classifier's dimensions).
struct ClassifyInputs {
  storage::SegmentRecord segment;
  std::optional<KeyframeNotice> keyframe;
  std::vector<engine::Codebook> codebooks;  // per classifier feature type
};

ClassifyInputs ReadClassifyInputs(storage::Connection& c, const ClassifyInstanceRequest& request, const engine::EsammeModel& model) {
  RequireMap(c, request.map);
  RequireClassifiable(storage::FindInstance(c, request.map, request.instance, false), request);
  ClassifyInputs out;
  const auto segment = storage::LatestInstanceSegment(c, request.map, request.instance);
  if (!segment) {
    throw Error(ErrorCode::kConflict, "instance " + std::to_string(request.instance) +
                                          " has no segment to classify (entered by hand, or its segments were forgotten)",
                "instance");
  }
  out.segment = *segment;
  out.keyframe = LoadKeyframeNotice(c, request.map, segment->keyframe_id);
  for (std::size_t t = 0; t < model.feature_types.size(); ++t) {
    const std::string& type = model.feature_types[t];
    const auto book = storage::GetCodebook(c, request.map, type);
    if (!book) throw Error(ErrorCode::kUnprocessable, "map '" + request.map + "' has no codebook of '" + type + "'", "classifier");
    if (book->words != model.feature_dims[t]) {
      throw Error(ErrorCode::kUnprocessable, "the codebook of '" + type + "' has " + std::to_string(book->words) +
                                                 " words, the classifier expects " + std::to_string(model.feature_dims[t]),
                  "classifier");
    }
    out.codebooks.push_back({book->words, book->dims, book->centres});
  }
  return out;
}

// The segment's points in the map frame and where the sensor stood: the keyframe's depth inside the segment's box
// when the keyframe is kept, else the segment's stored sample seen from 1 m above its centroid.
struct SegmentCloud {
  std::vector<Eigen::Vector3f> points_m;
  Eigen::Vector3d sensor_m = Eigen::Vector3d::Zero();
};

SegmentCloud CloudOfSegment(const ClassifyInputs& in) {
  SegmentCloud out;
  if (in.keyframe) {
    const Eigen::Vector3d min_m(in.segment.min[0], in.segment.min[1], in.segment.min[2]);
    const Eigen::Vector3d max_m(in.segment.max[0], in.segment.max[1], in.segment.max[2]);
    const auto cloud_m = engine::BackProjectRaw(in.keyframe->depth_mm, 1000.0, in.keyframe->K, in.keyframe->X_MapCamera);
    out.points_m = engine::PointsInBox(cloud_m, min_m, max_m, kSegmentMarginM);
    out.sensor_m = in.keyframe->X_MapCamera.translation();
  } else {
    out.points_m = SamplePoints(in.segment.sample);
    out.sensor_m = Eigen::Vector3d(in.segment.centroid[0], in.segment.centroid[1], in.segment.centroid[2] + 1.0);
  }
  return out;
}

// Features of the classifier's types, their bags of words (result.types) and the prediction (result.label,
// result.distribution); answers the distribution by class name.
engine::LabelWeights PredictClasses(const engine::EsammeModel& model, const ClassifyInputs& in, const SegmentCloud& cloud,
                                    const engine::ExtractionParams& params, InstanceClassificationResult& result) {
  const auto extracted = engine::ExtractFeatures(cloud.points_m, cloud.sensor_m, model.feature_types, params);
  std::vector<engine::FeatureMatrix> features;
  for (std::size_t t = 0; t < model.feature_types.size(); ++t) {
    const std::string& type = model.feature_types[t];
    const engine::Codebook& book = in.codebooks[t];
    engine::TypedBag coded = engine::BagOfWordsOfType(extracted, type, book);
    InstanceClassificationResult::PerType per;
    per.type = type;
    per.features = coded.coded;
    per.bag = std::move(coded.bag);
    engine::FeatureMatrix m(1, book.words);
    for (int w = 0; w < book.words; ++w) m(0, w) = static_cast<float>(per.bag[static_cast<std::size_t>(w)]);
    features.push_back(std::move(m));
    result.types.push_back(std::move(per));
  }
  const auto total = std::accumulate(result.types.begin(), result.types.end(), 0,
                                     [](int sum, const auto& p) { return sum + p.features; });
  if (total == 0) {
    throw Error(ErrorCode::kUnprocessable, "no feature of the classifier's types could be extracted from the segment's " +
                                               std::to_string(cloud.points_m.size()) + " points", "instance");
  }
  const engine::EsammePrediction prediction = engine::PredictEsamme(model, features).front();
  result.label = model.class_names[static_cast<std::size_t>(prediction.label)];
  engine::LabelWeights classified;
  for (std::size_t k = 0; k < prediction.distribution.size(); ++k) {
    result.distribution.emplace_back(model.class_names[k], prediction.distribution[k]);
    classified[model.class_names[k]] = prediction.distribution[k];
  }
  return classified;
}

// Stores the classification (one row per instance) and what it means for the instance's labels (result.applied,
// label_source, labels); a labelled event when the class the instance shows (a classifier's label, never
// 'unknown') differs from the one the previous classification showed.
void StoreClassification(storage::Connection& c, const ClassifyInstanceRequest& request, const ClassifyInputs& in,
                         const engine::LabelWeights& classified, std::int64_t stamp_ns, InstanceClassificationResult& result) {
  RequireMap(c, request.map);
  const auto found = storage::FindInstance(c, request.map, request.instance, false);
  const storage::InstanceRecord& r = RequireClassifiable(found, request);
  storage::InstanceClassificationRecord row;
  row.instance_id = request.instance;
  row.map_id = request.map;
  row.classifier = request.classifier;
  row.label = result.label;
  row.distribution = classified;
  row.segment_id = in.segment.id;
  row.keyframe_id = result.keyframe;
  row.stamp_ns = stamp_ns;
  const auto before = storage::FindInstanceClassification(c, request.map, request.instance);
  storage::UpsertInstanceClassification(c, row);
  const engine::LabelWeights& named = r.labels;
  const engine::EffectiveLabels effective = engine::EffectiveObjectLabels(named, r.label_locked, classified);
  result.applied = engine::ClassifierLabelApplies(named, r.label_locked);
  result.label_source = engine::LabelSourceName(effective.source);
  result.labels = effective.distribution;
  const std::optional<std::string> shown = engine::ShownClassifierClass(effective);
  const std::optional<std::string> shown_before =
      before ? engine::ShownClassifierClass(engine::EffectiveObjectLabels(named, r.label_locked, before->distribution))
             : std::nullopt;
  if (shown && shown != shown_before) {
    result.event = InsertLabelledEvent(c, request.map, request.instance, *shown, "classifier", stamp_ns,
                                       engine::ClassifiedExplanation(request.classifier), effective.distribution);
  }
}

}  // namespace

InstanceClassificationResult ClassifierService::ClassifyInstance(const ClassifyInstanceRequest& request) {
  CheckClassifyRequest(request);
  // Map and instance first (404 in path order), then the classifier and what its types need in the map.
  store_.Read([&](storage::Connection& c) {
    RequireMap(c, request.map);
    RequireClassifiable(storage::FindInstance(c, request.map, request.instance, false), request);
  });
  std::shared_ptr<const engine::EsammeModel> model;
  try {
    model = Model(request.classifier);
  } catch (const Error& e) {
    if (e.code() == ErrorCode::kNotFound) {
      throw Error(ErrorCode::kNotFound, "classifier '" + request.classifier + "' does not exist", "classifier");
    }
    throw;
  }
  for (const std::string& type : model->feature_types) {
    if (!ServerExtracts(type)) {
      throw Error(ErrorCode::kUnprocessable, "the classifier's feature type '" + type.substr(0, 40) +
                                                 "' cannot be extracted from a segment (the server extracts fpfh, shot and spd)",
                  "classifier");
    }
  }
  const ClassifyInputs in = store_.Read([&](storage::Connection& c) { return ReadClassifyInputs(c, request, *model); });
  // The heavy part outside any transaction: the segment's points, the features, the bags of words, the prediction.
  const SegmentCloud cloud = CloudOfSegment(in);
  if (cloud.points_m.size() < static_cast<std::size_t>(request.min_points)) {
    throw Error(ErrorCode::kUnprocessable, "the instance's segment has " + std::to_string(cloud.points_m.size()) +
                                               " points; at least " + std::to_string(request.min_points) +
                                               " are needed (min_points)", "instance");
  }
  engine::ExtractionParams params = features_.settings().extraction;
  params.keypoint_voxel_m = request.keypoint_spacing_m;
  InstanceClassificationResult result;
  const engine::LabelWeights classified = PredictClasses(*model, in, cloud, params, result);
  result.instance = request.instance;
  result.classifier = request.classifier;
  result.segment = in.segment.id;
  if (in.keyframe) result.keyframe = in.segment.keyframe_id;
  result.points = static_cast<int>(cloud.points_m.size());
  store_.Write([&](storage::Connection& c) { StoreClassification(c, request, in, classified, clock_.NowNs(), result); });
  return result;
}

}  // namespace anchordb::services
