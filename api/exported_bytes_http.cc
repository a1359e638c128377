// Exported bytes as an HTTP response: format -> content type, typed description -> X- headers.
#include "api/exported_bytes_http.h"

#include <string>
#include <utility>

namespace anchordb::api {

using services::BytesFormat;
using services::RawElement;

const char* ContentTypeOf(BytesFormat format) {
  switch (format) {
    case BytesFormat::kPng: return "image/png";
    case BytesFormat::kPgm: return "image/x-portable-graymap";
    case BytesFormat::kMapServerYaml: return "application/yaml";
    case BytesFormat::kPcd: return "application/x-pcd";
    case BytesFormat::kPly: return "application/x-ply";
    case BytesFormat::kRaw:
    case BytesFormat::kOctomapBinary: return "application/octet-stream";
  }
  return "application/octet-stream";
}

namespace {

const char* ElementName(RawElement element) {
  switch (element) {
    case RawElement::kNone: return nullptr;
    case RawElement::kU8ImageOrder: return "u8-image-order";
    case RawElement::kU8MaskCellOrder: return "u8-mask-cell-order";
    case RawElement::kU16LabelCellOrder: return "u16-label-cell-order";
    case RawElement::kF32LogOddsCellOrder: return "f32-log-odds-cell-order";
    case RawElement::kF32Metres: return "f32-metres";
    case RawElement::kF32Weight: return "f32-weight";
  }
  return nullptr;
}

template <typename T>
void PutIf(std::map<std::string, std::string>& headers, const char* name, const std::optional<T>& value) {
  if (value) headers[name] = std::to_string(*value);
}

}  // namespace

Response BytesResponse(services::ExportedLayer e) {
  Response r{200, ContentTypeOf(e.format), std::move(e.body), {}, {}};
  if (const char* element = ElementName(e.element)) r.headers["X-Element"] = element;
  PutIf(r.headers, "X-Image-Width", e.image_width_px);
  PutIf(r.headers, "X-Image-Height", e.image_height_px);
  PutIf(r.headers, "X-Grid-Width", e.grid_width_cells);
  PutIf(r.headers, "X-Grid-Height", e.grid_height_cells);
  PutIf(r.headers, "X-Layer-Version", e.layer_version);
  PutIf(r.headers, "X-Scene-Frames", e.scene_frames);
  PutIf(r.headers, "X-Points", e.points);
  PutIf(r.headers, "X-Octomap-Version", e.octomap_version);
  if (e.frame) r.headers["X-Frame"] = *e.frame == services::CoordinateFrame::kMap ? "map" : "camera";
  if (e.truncated) r.headers["X-Truncated"] = "true";
  if (e.file_name) r.headers["Content-Disposition"] = "attachment; filename=\"" + *e.file_name + "\"";
  return r;
}

}  // namespace anchordb::api
