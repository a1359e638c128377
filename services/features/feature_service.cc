#include "services/features/feature_service.h"

#include <cmath>
#include <limits>

#include "schema/error.h"
#include "services/common/require.h"
#include "storage/feature_documents.h"
#include "storage/scene_repository.h"

namespace anchordb::services {
namespace {

void CheckFinite(const Eigen::Vector3d& v, const std::string& field) {
  if (!v.allFinite()) throw Error(ErrorCode::kInvalidArgument, field + " must be finite [m]", field);
}

void CheckTimes(const std::optional<std::int64_t>& since, const std::optional<std::int64_t>& until) {
  if (since && until && *until <= *since) throw Error(ErrorCode::kInvalidArgument, "until must be after since", "until");
}

// The descriptor length `type` must have in `map`: fixed for known types, the stored one for client types.
std::optional<int> ExpectedDims(storage::Connection& c, const std::string& map, const std::string& type) {
  if (auto dims = engine::FeatureTypeDims(type)) return dims;
  return storage::StoredFeatureDims(c, map, type);
}

// The type, sphere, box and time range of a query.
void ValidateShapes(const storage::FeatureFilter& query) {
  if (!query.type.empty()) engine::FeatureTypeDims(query.type);
  if (query.near_m) {
    CheckFinite(*query.near_m, "near");
    if (!(query.radius_m >= 0.0 && std::isfinite(query.radius_m))) {
      throw Error(ErrorCode::kInvalidArgument, "radius must be a non-negative number [m]", "radius");
    }
  }
  if (query.box_min_m) {
    CheckFinite(*query.box_min_m, "bbox");
    CheckFinite(*query.box_max_m, "bbox");
    if ((query.box_max_m->array() < query.box_min_m->array()).any()) {
      throw Error(ErrorCode::kInvalidArgument, "bbox max must not be below min", "bbox");
    }
  }
  CheckTimes(query.since_ns, query.until_ns);
}

engine::Codebook AsBook(const storage::CodebookRecord& r) { return {r.words, r.dims, r.centres}; }

}  // namespace

FeatureService::FeatureService(storage::Store& store, JobService& jobs, FeatureSettings settings, const Clock& clock)
    : store_(store), jobs_(jobs), settings_(std::move(settings)), clock_(clock) {
  JobKind kind;
  kind.name = "codebook";
  kind.first_stage = "reading";
  kind.needs_map = true;
  kind.run = [&store = store_, &clock = clock_](JobContext& job) -> std::optional<std::string> {
    const storage::CodebookJobRequest r =
        storage::DecodeCodebookRequest(job.request(), "job " + std::to_string(job.id()) + "'s request");
    const std::string& map = *job.map();
    // Captures the store and the clock, not the service: the job service (declared before it) may still run this
    // while the capabilities are destroyed.
    // k-means runs outside the write lock on a snapshot; the codewords are assigned in one write afterwards, to
    // every feature of the type then stored (also those added meanwhile).
    FeatureQuery all;
    all.type = r.type;
    all.limit = std::numeric_limits<int>::max();
    const auto features = store.Read([&](storage::Connection& c) { return storage::ListFeatures(c, map, all); });
    if (features.empty()) throw Error(ErrorCode::kUnprocessable, "no features of type '" + r.type + "'");
    const int dims = static_cast<int>(features.front().descriptor.size());
    std::vector<float> data;
    data.reserve(features.size() * static_cast<std::size_t>(dims));
    for (const auto& f : features) data.insert(data.end(), f.descriptor.begin(), f.descriptor.end());
    job.Progress("clustering", 0.1);
    const engine::Codebook book = engine::BuildCodebook(data, dims, r.words, r.seed);
    job.Progress("assigning", 0.8);
    const std::int64_t assigned = store.Write([&](storage::Connection& c) {
      storage::CodebookRecord record{map, r.type, book.words, book.dims, r.seed, book.centres,
                                     static_cast<std::int64_t>(features.size()), clock.NowNs()};
      storage::UpsertCodebook(c, record);
      std::int64_t count = 0;
      for (const auto& f : storage::ListFeatures(c, map, all)) {
        storage::SetCodeword(c, f.id, engine::NearestWord(book, f.descriptor));
        ++count;
      }
      return count;
    });
    return storage::EncodeCodebookResult(
        {r.type, book.words, book.dims, static_cast<std::int64_t>(features.size()), assigned});
  };
  jobs_.Register(std::move(kind));
}

const engine::DedupThreshold& FeatureService::ThresholdOf(const std::string& type) const {
  if (type == "fpfh") return settings_.fpfh;
  if (type == "shot") return settings_.shot;
  if (type == "spd") return settings_.spd;
  return settings_.other;
}

FeatureBatchResult FeatureService::AddBatch(const std::string& map, const FeatureBatch& batch) {
  engine::FeatureTypeDims(batch.type);  // throws for an unknown type
  if (batch.features.empty()) throw Error(ErrorCode::kInvalidArgument, "a batch needs at least one feature", "features");
  if (static_cast<int>(batch.features.size()) > settings_.max_batch) {
    throw Error(ErrorCode::kPayloadTooLarge, "at most " + std::to_string(settings_.max_batch) + " features in one batch",
                "features");
  }
  const engine::DedupThreshold threshold = ThresholdOf(batch.type);
  const std::int64_t now = clock_.NowNs();
  return store_.Write([&](storage::Connection& c) {
    RequireMap(c, map);
    std::optional<int> dims = ExpectedDims(c, map, batch.type);
    const auto codebook = storage::GetCodebook(c, map, batch.type);
    std::vector<std::int64_t> stamps;
    for (std::size_t i = 0; i < batch.features.size(); ++i) {
      const FeatureItem& f = batch.features[i];
      const std::string field = "features[" + std::to_string(i) + "]";
      if (f.descriptor.empty()) throw Error(ErrorCode::kInvalidArgument, "a descriptor needs values", field + ".descriptor");
      if (!dims) dims = static_cast<int>(f.descriptor.size());
      if (static_cast<int>(f.descriptor.size()) != *dims) {
        throw Error(ErrorCode::kUnprocessable, "descriptors of type '" + batch.type + "' have " + std::to_string(*dims) +
                                                   " values, not " + std::to_string(f.descriptor.size()), field + ".descriptor");
      }
      for (float v : f.descriptor) {
        if (!std::isfinite(v)) throw Error(ErrorCode::kInvalidArgument, "descriptor values must be finite", field + ".descriptor");
      }
      CheckFinite(f.anchor_m, field + ".anchor_m");
      std::int64_t stamp = batch.stamp_ns.value_or(now);
      if (f.keyframe) {
        const auto kf = storage::FindKeyframe(c, map, *f.keyframe, false);
        if (!kf) throw Error(ErrorCode::kNotFound, "keyframe " + std::to_string(*f.keyframe) + " does not exist", field + ".keyframe");
        if (!batch.stamp_ns) stamp = kf->stamp_ns;
      }
      stamps.push_back(stamp);
    }
    // Insert one by one, so that duplicates within the batch are found among its own earlier features too.
    FeatureBatchResult result;
    for (std::size_t i = 0; i < batch.features.size(); ++i) {
      const FeatureItem& f = batch.features[i];
      std::optional<std::int64_t> duplicate_of;
      for (const auto& near : storage::FeaturesNear(c, map, batch.type, f.anchor_m, threshold.radius_m)) {
        if (engine::IsDuplicate(f.descriptor, f.anchor_m, near.descriptor, near.anchor_m, threshold)) {
          duplicate_of = near.id;
          break;
        }
      }
      if (duplicate_of) {
        result.ids.push_back(*duplicate_of);
        result.duplicate.push_back(true);
        ++result.duplicates;
        continue;
      }
      storage::FeatureRecord r;
      r.map = map;
      r.type = batch.type;
      r.descriptor = f.descriptor;
      r.anchor_m = f.anchor_m;
      r.keyframe = f.keyframe;
      r.stamp_ns = stamps[i];
      if (codebook) r.codeword = engine::NearestWord(AsBook(*codebook), f.descriptor);
      result.ids.push_back(storage::InsertFeature(c, r));
      result.duplicate.push_back(false);
      ++result.inserted;
    }
    return result;
  });
}

FeaturePage FeatureService::List(const std::string& map, const FeatureQuery& query) {
  if (query.limit < 1 || query.limit > 10000) throw Error(ErrorCode::kInvalidArgument, "limit must be in [1, 10000]", "limit");
  ValidateShapes(query);
  return store_.Read([&](storage::Connection& c) {
    RequireMap(c, map);
    FeaturePage page;
    page.features = storage::ListFeatures(c, map, query);
    if (static_cast<int>(page.features.size()) == query.limit) page.next_after = page.features.back().id;
    return page;
  });
}

JobTicket FeatureService::SubmitCodebook(const std::string& map, const CodebookRequest& request) {
  engine::FeatureTypeDims(request.type);
  if (request.words < 2 || request.words > settings_.max_codebook_words) {
    throw Error(ErrorCode::kInvalidArgument, "words must be in [2, " + std::to_string(settings_.max_codebook_words) + "]", "words");
  }
  const std::int64_t stored = store_.Read([&](storage::Connection& c) {
    RequireMap(c, map);
    return storage::CountFeatures(c, map, request.type);
  });
  if (stored < request.words) {
    throw Error(ErrorCode::kUnprocessable, "a codebook of " + std::to_string(request.words) + " words needs at least as many " +
                                               request.type + " features (" + std::to_string(stored) + " stored)", "words");
  }
  return jobs_.Submit("codebook", map, storage::EncodeCodebookRequest({request.type, request.words, request.seed}));
}

CodebookView FeatureService::GetCodebook(const std::string& map, const std::string& type) {
  engine::FeatureTypeDims(type);
  return store_.Read([&](storage::Connection& c) {
    RequireMap(c, map);
    auto book = storage::GetCodebook(c, map, type);
    if (!book) throw Error(ErrorCode::kNotFound, "no codebook of type '" + type + "' in map '" + map + "'", "type");
    return *book;
  });
}

BowResult FeatureService::BagOfWords(const std::string& map, const BowQuery& q) {
  engine::FeatureTypeDims(q.type);
  const int shapes = (q.near_m ? 1 : 0) + (q.box_min_m ? 1 : 0) + (q.polygon_m.empty() ? 0 : 1);
  if (shapes != 1) {
    throw Error(ErrorCode::kInvalidArgument, "give exactly one of near+radius, bbox or polygon (or region)", "region");
  }
  if (!q.polygon_m.empty() && q.polygon_m.size() < 3) {
    throw Error(ErrorCode::kInvalidArgument, "a polygon needs at least 3 vertices", "polygon");
  }
  for (const auto& v : q.polygon_m) {
    if (!v.allFinite()) throw Error(ErrorCode::kInvalidArgument, "polygon vertices must be finite [m]", "polygon");
  }
  FeatureQuery f;
  f.type = q.type;
  f.near_m = q.near_m;
  f.radius_m = q.radius_m;
  f.box_min_m = q.box_min_m;
  f.box_max_m = q.box_max_m;
  f.since_ns = q.since_ns;
  f.until_ns = q.until_ns;
  f.descriptors = false;
  f.limit = std::numeric_limits<int>::max();
  if (!q.polygon_m.empty()) {  // the polygon's bounding box (all heights) in the R*Tree, then the exact test
    Eigen::Vector2d lo = q.polygon_m[0], hi = q.polygon_m[0];
    for (const auto& v : q.polygon_m) {
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
    f.box_min_m = Eigen::Vector3d(lo.x(), lo.y(), -1e9);
    f.box_max_m = Eigen::Vector3d(hi.x(), hi.y(), 1e9);
  }
  ValidateShapes(f);
  return store_.Read([&](storage::Connection& c) {
    RequireMap(c, map);
    auto book = storage::GetCodebook(c, map, q.type);
    if (!book) throw Error(ErrorCode::kNotFound, "no codebook of type '" + q.type + "' in map '" + map + "'", "type");
    std::vector<int> words;
    for (const auto& feature : storage::ListFeatures(c, map, f)) {
      if (!q.polygon_m.empty() && !engine::InsidePolygon(q.polygon_m, feature.anchor_m.head<2>())) continue;
      if (feature.codeword) words.push_back(*feature.codeword);
    }
    BowResult r;
    r.type = q.type;
    r.words = book->words;
    r.features = static_cast<int>(words.size());
    r.histogram = engine::BagOfWords(words, book->words);
    return r;
  });
}

}  // namespace anchordb::services
