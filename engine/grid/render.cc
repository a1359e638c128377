#include "engine/grid/render.h"

#include <cmath>

#include "engine/image/png_codec.h"

namespace anchordb::engine {

GreyImage ProbabilityToImage(const ProbabilityGrid& p) {
  const GridGeometry& g = p.geometry;
  GreyImage img{g.width_cells, g.height_cells, std::vector<std::uint8_t>(g.CellCount())};
  for (int iy = 0; iy < g.height_cells; ++iy) {
    const int row = g.height_cells - 1 - iy;
    for (int ix = 0; ix < g.width_cells; ++ix) {
      img.pixels[static_cast<std::size_t>(row) * g.width_cells + ix] =
          static_cast<std::uint8_t>(std::lround((1.0 - p.at(ix, iy)) * 255.0));
    }
  }
  return img;
}

GreyImage OccupancyToImage(const OccupancyGrid& o, const OccupancyThresholds& t) {
  const GridGeometry& g = o.geometry;
  GreyImage img{g.width_cells, g.height_cells, std::vector<std::uint8_t>(g.CellCount())};
  for (int iy = 0; iy < g.height_cells; ++iy) {
    const int row = g.height_cells - 1 - iy;
    for (int ix = 0; ix < g.width_cells; ++ix) {
      const std::int8_t v = o.at(ix, iy);
      img.pixels[static_cast<std::size_t>(row) * g.width_cells + ix] = IsOccupied(v, t) ? 0 : IsFree(v, t) ? 254 : 205;
    }
  }
  return img;
}

std::string RenderLabelsPng(const LabelGrid& labels) {
  const GridGeometry& g = labels.geometry;
  PngImage img{g.width_cells, g.height_cells, 3, 8, {}};
  img.bytes.resize(img.row_bytes() * static_cast<std::size_t>(g.height_cells));
  for (int iy = 0; iy < g.height_cells; ++iy) {
    std::uint8_t* row = img.bytes.data() + img.row_bytes() * static_cast<std::size_t>(g.height_cells - 1 - iy);
    for (int ix = 0; ix < g.width_cells; ++ix) {
      const unsigned id = labels.at(ix, iy);
      // Golden-ratio hue spacing gives well separated colours for consecutive ids (red, green, blue).
      std::uint8_t* px = row + 3 * ix;
      px[0] = id == 0 ? 255 : static_cast<std::uint8_t>(60 + (id * 151) % 180);
      px[1] = id == 0 ? 255 : static_cast<std::uint8_t>(60 + (id * 57) % 180);
      px[2] = id == 0 ? 255 : static_cast<std::uint8_t>(60 + (id * 97) % 180);
    }
  }
  return EncodePngImage(img, 1);
}

}  // namespace anchordb::engine
