#include "storage/segmentation_documents.h"

#include "storage/document_codec.h"

namespace anchordb::storage {
namespace {
constexpr std::uint16_t kSegmentationVersion = 1;
}  // namespace

std::string EncodeSegmentationRequest(const SegmentationJobRequest& r) {
  DocumentWriter w(DocumentKind::kSegmentationRequest, kSegmentationVersion);
  w.Text(r.source).Ints(r.keyframes).Int(r.max_keyframes).Real(r.max_range_m).Optional(r.shape_model);
  w.Bool(r.use_stored_shape_model).Real(r.match_iou).Optional(r.staging).Count(r.params.size());
  for (const auto& [name, value] : r.params) w.Text(name).Real(value);
  return w.Finish();
}

SegmentationJobRequest DecodeSegmentationRequest(std::string_view stored, const std::string& what) {
  DocumentReader d(stored, DocumentKind::kSegmentationRequest, kSegmentationVersion, what);
  SegmentationJobRequest r;
  r.source = d.Text();
  r.keyframes = d.Ints();
  r.max_keyframes = d.Int();
  r.max_range_m = d.Real();
  r.shape_model = d.OptionalText();
  r.use_stored_shape_model = d.Bool();
  r.match_iou = d.Real();
  r.staging = d.OptionalInt();
  r.params.resize(d.Count());
  for (auto& [name, value] : r.params) {
    name = d.Text();
    value = d.Real();
  }
  d.End();
  return r;
}

std::string EncodeSegmentationResult(const SegmentationJobResult& r) {
  DocumentWriter w(DocumentKind::kSegmentationResult, kSegmentationVersion);
  w.Text(r.map_id).Text(r.source).Optional(r.shape_model).Bool(r.octomap_truncated).Int(r.bridges_cut);
  w.Int(r.input_points).Int(r.thinned_points).Int(r.remaining_points).Texts(r.planes).Int(r.small_clusters);
  w.Int(r.flying_dropped).Optional(r.floor_z_m).Count(r.segments.size());
  for (const SegmentationJobSegment& s : r.segments) {
    w.Text(s.action).Int(s.furniture).Text(s.label).Real(s.label_probability).Text(s.classifier).Real(s.x_m);
    w.Real(s.y_m).Real(s.extent_x_m).Real(s.extent_y_m).Real(s.yaw_rad).Real(s.height_m).Int(s.points);
  }
  w.Real(r.seconds);
  return w.Finish();
}

SegmentationJobResult DecodeSegmentationResult(std::string_view stored, const std::string& what) {
  DocumentReader d(stored, DocumentKind::kSegmentationResult, kSegmentationVersion, what);
  SegmentationJobResult r;
  r.map_id = d.Text();
  r.source = d.Text();
  r.shape_model = d.OptionalText();
  r.octomap_truncated = d.Bool();
  r.bridges_cut = d.Int();
  r.input_points = d.Int();
  r.thinned_points = d.Int();
  r.remaining_points = d.Int();
  r.planes = d.Texts();
  r.small_clusters = d.Int();
  r.flying_dropped = d.Int();
  r.floor_z_m = d.OptionalReal();
  r.segments.resize(d.Count());
  for (SegmentationJobSegment& s : r.segments) {
    s.action = d.Text();
    s.furniture = d.Int();
    s.label = d.Text();
    s.label_probability = d.Real();
    s.classifier = d.Text();
    s.x_m = d.Real();
    s.y_m = d.Real();
    s.extent_x_m = d.Real();
    s.extent_y_m = d.Real();
    s.yaw_rad = d.Real();
    s.height_m = d.Real();
    s.points = d.Int();
  }
  r.seconds = d.Real();
  d.End();
  return r;
}

}  // namespace anchordb::storage
