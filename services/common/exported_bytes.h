#pragma once
// Bytes a service hands out as they are (a layer as PNG/PGM/YAML/raw, a keyframe image, a cloud, an OctoMap file):
// the body, its format and what describes it (element type of a raw array, image and grid sizes, point counts, the
// frame, versions). Typed: api/exported_bytes_http.h alone turns them into a content type and headers.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

namespace anchordb::services {

enum class BytesFormat : std::uint8_t {
  kPng,
  kPgm,
  kMapServerYaml,  // a ROS map_server YAML
  kRaw,            // a bare array; `element` says its cell type and order
  kPcd,
  kPly,
  kOctomapBinary,  // an OctoMap .bt or .ot file
};

// What one cell of a raw array is.
enum class RawElement : std::uint8_t {
  kNone,
  kU8ImageOrder,         // an occupancy image's pixels, row 0 on top
  kU8MaskCellOrder,      // a mask over grid cells, row 0 at the origin
  kU16LabelCellOrder,    // label ids over grid cells
  kF32LogOddsCellOrder,  // log-odds over grid cells
  kF32Metres,            // a depth image in metres
  kF32Weight,            // a scene model's reliability weight per pixel
};

enum class CoordinateFrame : std::uint8_t { kMap, kCamera };

struct ExportedLayer {
  BytesFormat format = BytesFormat::kRaw;
  std::string body;
  RawElement element = RawElement::kNone;
  std::optional<int> image_width_px, image_height_px;      // a scene layer's image
  std::optional<int> grid_width_cells, grid_height_cells;  // a grid layer
  std::optional<std::int64_t> layer_version;
  std::optional<std::int64_t> scene_frames;  // frames the scene model has seen
  std::optional<std::size_t> points;         // a cloud's point count
  std::optional<CoordinateFrame> frame;      // a cloud's frame
  bool truncated = false;                    // a cloud cut at its limit
  std::optional<std::int64_t> octomap_version;
  std::optional<std::string> file_name;      // the name a download is saved as
};

}  // namespace anchordb::services
