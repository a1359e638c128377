#include "storage/shape_documents.h"

#include "storage/document_codec.h"

namespace anchordb::storage {
namespace {
constexpr std::uint16_t kShapeDocumentVersion = 1;

void PutShapeParams(DocumentWriter& w, const ShapeModelParamsRecord& p) {
  w.Real(p.voxel_m).Real(p.normal_radius_m).Real(p.boundary_angle_rad).Real(p.keypoint_spacing_m).Real(p.shot_radius_m)
      .Int(p.codebook_size).Int(p.activated_words).Int(p.azimuth_bins).Int(p.polar_bins).Real(p.sphere_radius_m)
      .Real(p.detection_spacing_m).Real(p.accept_fraction).Real(p.merge_distance_m).Int(p.max_keypoints)
      .Int(static_cast<std::int64_t>(p.seed)).Real(p.size_weight).Real(p.size_bandwidth).Real(p.size_floor);
}

ShapeModelParamsRecord TakeShapeParams(DocumentReader& d) {
  ShapeModelParamsRecord p;
  p.voxel_m = d.Real();
  p.normal_radius_m = d.Real();
  p.boundary_angle_rad = d.Real();
  p.keypoint_spacing_m = d.Real();
  p.shot_radius_m = d.Real();
  p.codebook_size = d.SmallInt();
  p.activated_words = d.SmallInt();
  p.azimuth_bins = d.SmallInt();
  p.polar_bins = d.SmallInt();
  p.sphere_radius_m = d.Real();
  p.detection_spacing_m = d.Real();
  p.accept_fraction = d.Real();
  p.merge_distance_m = d.Real();
  p.max_keypoints = d.SmallInt();
  p.seed = static_cast<std::uint64_t>(d.Int());
  p.size_weight = d.Real();
  p.size_bandwidth = d.Real();
  p.size_floor = d.Real();
  return p;
}

void PutShapeOptions(DocumentWriter& w, const ShapeModelOptionsRecord& o) {
  w.Text(o.name);
  PutShapeParams(w, o.params);
  w.Int(o.mesh_views).Count(o.parts.size());
  for (const auto& part : o.parts) w.Text(part.part).Text(part.category).Bool(part.mesh).Int(part.count);
}

ShapeModelOptionsRecord TakeShapeOptions(DocumentReader& d) {
  ShapeModelOptionsRecord o;
  o.name = d.Text();
  o.params = TakeShapeParams(d);
  o.mesh_views = d.Int();
  for (std::size_t n = d.Count(); n > 0; --n) {
    ShapeTrainingPartRecord part;
    part.part = d.Text();
    part.category = d.Text();
    part.mesh = d.Bool();
    part.count = d.Int();
    o.parts.push_back(std::move(part));
  }
  return o;
}

}  // namespace

std::string EncodeShapeModelOptions(const ShapeModelOptionsRecord& options) {
  DocumentWriter w(DocumentKind::kShapeModelOptions, kShapeDocumentVersion);
  PutShapeOptions(w, options);
  return w.Finish();
}

ShapeModelOptionsRecord DecodeShapeModelOptions(std::string_view stored, const std::string& what) {
  DocumentReader d(stored, DocumentKind::kShapeModelOptions, kShapeDocumentVersion, what);
  ShapeModelOptionsRecord o = TakeShapeOptions(d);
  d.End();
  return o;
}

std::string EncodeShapeModelReport(const ShapeModelReportRecord& r) {
  DocumentWriter w(DocumentKind::kShapeModelReport, kShapeDocumentVersion);
  w.Count(r.categories.size());
  for (const auto& c : r.categories) w.Text(c.category).Int(c.samples).Int(c.keypoints);
  w.Int(r.samples).Int(r.keypoints).Int(r.codebook_size).Int(r.non_empty_bins).Int(r.mesh_views).Real(r.train_seconds);
  return w.Finish();
}

ShapeModelReportRecord DecodeShapeModelReport(std::string_view stored, const std::string& what) {
  DocumentReader d(stored, DocumentKind::kShapeModelReport, kShapeDocumentVersion, what);
  ShapeModelReportRecord r;
  for (std::size_t n = d.Count(); n > 0; --n) {
    ShapeCategoryReportRecord c;
    c.category = d.Text();
    c.samples = d.Int();
    c.keypoints = d.Int();
    r.categories.push_back(std::move(c));
  }
  r.samples = d.Int();
  r.keypoints = d.Int();
  r.codebook_size = d.Int();
  r.non_empty_bins = d.Int();
  r.mesh_views = d.Int();
  r.train_seconds = d.Real();
  d.End();
  return r;
}

std::string EncodeShapeTrainingRequest(const ShapeTrainingRequestRecord& r) {
  DocumentWriter w(DocumentKind::kShapeTrainingRequest, kShapeDocumentVersion);
  PutShapeOptions(w, r.options);
  w.Int(r.staging);
  return w.Finish();
}

ShapeTrainingRequestRecord DecodeShapeTrainingRequest(std::string_view stored, const std::string& what) {
  DocumentReader d(stored, DocumentKind::kShapeTrainingRequest, kShapeDocumentVersion, what);
  ShapeTrainingRequestRecord r;
  r.options = TakeShapeOptions(d);
  r.staging = d.Int();
  d.End();
  return r;
}

std::string EncodeShapeTrainingResult(const ShapeTrainingResultRecord& r) {
  return DocumentWriter(DocumentKind::kShapeTrainingResult, kShapeDocumentVersion)
      .Text(r.name)
      .Int(r.samples)
      .Int(r.keypoints)
      .Real(r.train_seconds)
      .Finish();
}

ShapeTrainingResultRecord DecodeShapeTrainingResult(std::string_view stored, const std::string& what) {
  DocumentReader d(stored, DocumentKind::kShapeTrainingResult, kShapeDocumentVersion, what);
  ShapeTrainingResultRecord r;
  r.name = d.Text();
  r.samples = d.Int();
  r.keypoints = d.Int();
  r.train_seconds = d.Real();
  d.End();
  return r;
}

}  // namespace anchordb::storage
