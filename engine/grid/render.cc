#include "engine/grid/render.h"

#include <cmath>
#include <opencv2/imgcodecs.hpp>

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
  cv::Mat img(g.height_cells, g.width_cells, CV_8UC3);
  for (int iy = 0; iy < g.height_cells; ++iy) {
    auto* row = img.ptr<cv::Vec3b>(g.height_cells - 1 - iy);
    for (int ix = 0; ix < g.width_cells; ++ix) {
      const unsigned id = labels.at(ix, iy);
      // Golden-ratio hue spacing gives well separated colours for consecutive ids.
      row[ix] = id == 0 ? cv::Vec3b(255, 255, 255)
                        : cv::Vec3b(static_cast<std::uint8_t>(60 + (id * 97) % 180),
                                    static_cast<std::uint8_t>(60 + (id * 57) % 180),
                                    static_cast<std::uint8_t>(60 + (id * 151) % 180));
    }
  }
  std::vector<std::uint8_t> buf;
  cv::imencode(".png", img, buf);
  return std::string(buf.begin(), buf.end());
}

}  // namespace anchordb::engine
