#include "storage/feature_repository.h"

#include "storage/dialect.h"

#include <algorithm>
#include <limits>

#include "schema/error.h"
#include "storage/blob_codec.h"
#include "storage/trained_model_rows.h"

namespace anchordb::storage {
namespace {

std::string EncodeFloats(const std::vector<float>& v, std::uint32_t rows) {
  const auto cols = static_cast<std::uint32_t>(rows ? v.size() / rows : v.size());
  if (rows <= 1) return EncodeBlob(BlobElement::kF32, {static_cast<std::uint32_t>(v.size())}, AsBytes(v));
  return EncodeBlob(BlobElement::kF32, {rows, cols}, AsBytes(v));
}

std::vector<float> DecodeFloats(const std::string& blob, std::size_t count, const char* what) {
  auto v = DecodeArray<float>(blob, BlobElement::kF32, count);
  if (!v) throw Error(ErrorCode::kInternal, std::string("stored ") + what + " blob does not match its row");
  return *v;
}

constexpr const char* kFeatureColumns =
    "f.id, f.map_id, f.type, f.dims, f.descriptor, f.x_m, f.y_m, f.z_m, f.keyframe_id, f.stamp_ns, f.codeword";

FeatureRecord ReadFeature(const Statement& s, bool descriptors) {
  FeatureRecord f;
  f.id = s.Int(0);
  f.map = s.Text(1);
  f.type = s.Text(2);
  if (descriptors) f.descriptor = DecodeFloats(s.Blob(4), static_cast<std::size_t>(s.Int(3)), "descriptor");
  f.anchor_m = Eigen::Vector3d(s.Double(5), s.Double(6), s.Double(7));
  f.keyframe = OptionalInt(s, 8);
  f.stamp_ns = s.Int(9);
  if (!s.IsNull(10)) f.codeword = static_cast<int>(s.Int(10));
  return f;
}

}  // namespace

std::int64_t InsertFeature(Connection& c, const FeatureRecord& f) {
  Statement s(c, "INSERT INTO features (map_id, type, dims, descriptor, x_m, y_m, z_m, keyframe_id, stamp_ns, codeword) "
                 "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?) RETURNING id");
  s.Bind(1, f.map).Bind(2, f.type).Bind(3, static_cast<std::int64_t>(f.descriptor.size()));
  s.BindBlob(4, EncodeFloats(f.descriptor, 1));
  s.Bind(5, f.anchor_m.x()).Bind(6, f.anchor_m.y()).Bind(7, f.anchor_m.z());
  BindOptional(s, 8, f.keyframe);
  s.Bind(9, f.stamp_ns);
  BindOptional(s, 10, f.codeword ? std::optional<std::int64_t>(*f.codeword) : std::nullopt);
  return s.RunReturningId();
}

std::vector<FeatureRecord> ListFeatures(Connection& c, const std::string& map, const FeatureFilter& q) {
  std::string sql = std::string("SELECT ") + kFeatureColumns + " FROM features f";
  const bool spatial = q.box_min_m.has_value() || q.near_m.has_value();
  sql += " WHERE f.map_id = ? AND f.id > ?";
  if (!q.type.empty()) sql += " AND f.type = ?";
  // The spatial index narrows by box (hi x, hi y, lo x, lo y, hi z, lo z); the exact test on the row follows.
  const std::string in_box = spatial ? PointInBox(c.engine(), {"feature_anchors", "id", "f.id", "f.x_m", "f.y_m", "f.z_m"},
                                                  {"?", "?", "?", "?", "?", "?"})
                                     : std::string();
  if (q.box_min_m) sql += " AND " + in_box + " AND f.x_m BETWEEN ? AND ? AND f.y_m BETWEEN ? AND ? AND f.z_m BETWEEN ? AND ?";
  if (q.near_m) {
    sql += " AND " + in_box + " AND (f.x_m - ?) * (f.x_m - ?) + (f.y_m - ?) * (f.y_m - ?) + (f.z_m - ?) * (f.z_m - ?) <= ?";
  }
  if (q.since_ns) sql += " AND f.stamp_ns >= ?";
  if (q.until_ns) sql += " AND f.stamp_ns < ?";
  if (q.keyframe) sql += " AND f.keyframe_id = ?";
  sql += " ORDER BY f.id LIMIT ?";
  Statement s(c, sql);
  int i = 1;
  s.Bind(i++, map);
  s.Bind(i++, q.after_id);
  if (!q.type.empty()) s.Bind(i++, q.type);
  auto bind_index_box = [&](const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {  // the order of BoxBounds
    for (const double bound : {hi.x(), hi.y(), lo.x(), lo.y(), hi.z(), lo.z()}) s.Bind(i++, bound);
  };
  if (q.box_min_m) {
    bind_index_box(*q.box_min_m, *q.box_max_m);
    for (int axis = 0; axis < 3; ++axis) {
      s.Bind(i++, (*q.box_min_m)[axis]);
      s.Bind(i++, (*q.box_max_m)[axis]);
    }
  }
  if (q.near_m) {
    const Eigen::Vector3d r = Eigen::Vector3d::Constant(q.radius_m);
    bind_index_box(*q.near_m - r, *q.near_m + r);
    for (int axis = 0; axis < 3; ++axis) {
      s.Bind(i++, (*q.near_m)[axis]);
      s.Bind(i++, (*q.near_m)[axis]);
    }
    s.Bind(i++, q.radius_m * q.radius_m);
  }
  if (q.since_ns) s.Bind(i++, *q.since_ns);
  if (q.until_ns) s.Bind(i++, *q.until_ns);
  if (q.keyframe) s.Bind(i++, *q.keyframe);
  s.Bind(i++, static_cast<std::int64_t>(q.limit));
  std::vector<FeatureRecord> out;
  while (s.Step()) out.push_back(ReadFeature(s, q.descriptors));
  return out;
}

std::optional<int> StoredFeatureDims(Connection& c, const std::string& map, const std::string& type) {
  Statement s(c, "SELECT dims FROM features WHERE map_id = ? AND type = ? LIMIT 1");
  s.Bind(1, map).Bind(2, type);
  if (!s.Step()) return std::nullopt;
  return static_cast<int>(s.Int(0));
}

std::vector<FeatureRecord> FeaturesNear(Connection& c, const std::string& map, const std::string& type,
                                        const Eigen::Vector3d& anchor_m, double radius_m) {
  FeatureFilter q;
  q.type = type;
  q.near_m = anchor_m;
  q.radius_m = radius_m;
  q.limit = std::numeric_limits<int>::max();
  return ListFeatures(c, map, q);
}

void SetCodeword(Connection& c, std::int64_t feature_id, int codeword) {
  Statement(c, "UPDATE features SET codeword = ? WHERE id = ?").Bind(1, static_cast<std::int64_t>(codeword)).Bind(2, feature_id).Run();
}

std::int64_t CountFeatures(Connection& c, const std::string& map, const std::string& type) {
  Statement s(c, type.empty() ? "SELECT COUNT(*) FROM features WHERE map_id = ?"
                              : "SELECT COUNT(*) FROM features WHERE map_id = ? AND type = ?");
  s.Bind(1, map);
  if (!type.empty()) s.Bind(2, type);
  s.Step();
  return s.Int(0);
}

void DeleteFeature(Connection& c, std::int64_t feature_id) {
  Statement(c, "DELETE FROM features WHERE id = ?").Bind(1, feature_id).Run();
}

void UpsertCodebook(Connection& c, const CodebookRecord& b) {
  Statement s(c, "INSERT INTO codebooks (map_id, type, words, dims, seed, centres, features, created_ns) "
                 "VALUES (?, ?, ?, ?, ?, ?, ?, ?) ON CONFLICT (map_id, type) DO UPDATE SET words = excluded.words, "
                 "dims = excluded.dims, seed = excluded.seed, centres = excluded.centres, features = excluded.features, "
                 "created_ns = excluded.created_ns");
  s.Bind(1, b.map).Bind(2, b.type).Bind(3, static_cast<std::int64_t>(b.words)).Bind(4, static_cast<std::int64_t>(b.dims));
  s.Bind(5, static_cast<std::int64_t>(b.seed)).BindBlob(6, EncodeFloats(b.centres, static_cast<std::uint32_t>(b.words)));
  s.Bind(7, b.features).Bind(8, b.created_ns);
  s.Run();
}

std::optional<CodebookRecord> GetCodebook(Connection& c, const std::string& map, const std::string& type) {
  Statement s(c, "SELECT words, dims, seed, centres, features, created_ns FROM codebooks WHERE map_id = ? AND type = ?");
  s.Bind(1, map).Bind(2, type);
  if (!s.Step()) return std::nullopt;
  CodebookRecord b;
  b.map = map;
  b.type = type;
  b.words = static_cast<int>(s.Int(0));
  b.dims = static_cast<int>(s.Int(1));
  b.seed = static_cast<std::uint64_t>(s.Int(2));
  b.centres = DecodeFloats(s.Blob(3), static_cast<std::size_t>(b.words) * static_cast<std::size_t>(b.dims), "codebook");
  b.features = s.Int(4);
  b.created_ns = s.Int(5);
  return b;
}

void UpsertClassifier(Connection& c, const ClassifierRecord& r) { trained_models::Upsert(c, "classifiers", r); }

std::optional<ClassifierRecord> GetClassifier(Connection& c, const std::string& name, bool with_model) {
  return trained_models::Get<ClassifierRecord>(c, "classifiers", name, with_model);
}

std::vector<ClassifierRecord> ListClassifiers(Connection& c) {
  return trained_models::List<ClassifierRecord>(c, "classifiers");
}

}  // namespace anchordb::storage
