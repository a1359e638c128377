#pragma once
// The ROS map_server file format: a YAML description and a grey image (PGM or PNG). Import keeps the image
// pixels as given, so export reproduces the same YAML values and the same pixels; occupancy is derived from the
// pixels with map_server's rules (trinary, scale or raw mode; negate; occupied/free thresholds).
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "engine/grid/grid.h"
#include "schema/types.h"

namespace anchordb::engine {

// 8-bit grey image in image order (row 0 at the top, as in the file).
struct GreyImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;
};

struct ParsedYaml {
  MapServerMeta meta;
  std::vector<std::string> ignored_keys;  // keys map_server does not know, reported back to the client
};

// Throws Error(kInvalidArgument) for unparsable YAML or missing keys, kUnprocessable for impossible values.
ParsedYaml ParseMapServerYaml(std::string_view yaml_text);
// YAML text whose values parse back to exactly the same numbers (shortest round-trip formatting).
std::string EmitMapServerYaml(const MapServerMeta& meta);

// Decodes PGM (P5/P2, maxval 255) or PNG (grey, grey+alpha, RGB, RGBA: channels averaged as map_server does).
// Throws Error(kInvalidArgument) for anything else. `max_pixels` bounds the decoded size.
GreyImage DecodeMapImage(std::string_view bytes, std::size_t max_pixels);
std::string EncodePgm(const GreyImage& image);
std::string EncodePng(const GreyImage& image);

GridGeometry GeometryOf(const GreyImage& image, const MapServerMeta& meta);
// The YAML describing a probability image of a grid (ProbabilityToImage, render.h) saved as `image`: the grid's
// resolution and origin, mode scale (written out), default thresholds.
MapServerMeta ScaleModeMeta(const GridGeometry& geometry, const std::string& image);
// map_server's interpretation of the pixels: -1 unknown, 0..100.
OccupancyGrid ToOccupancy(const GreyImage& image, const MapServerMeta& meta);

}  // namespace anchordb::engine
