#include "engine/grid/regions.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>

namespace anchordb::engine {

std::vector<Region> ExtractRegions(const ProbabilityGrid& probability, double threshold, double min_area_m2) {
  const GridGeometry& g = probability.geometry;
  cv::Mat mask(g.height_cells, g.width_cells, CV_8U);  // row = iy
  for (int iy = 0; iy < g.height_cells; ++iy) {
    auto* row = mask.ptr<std::uint8_t>(iy);
    for (int ix = 0; ix < g.width_cells; ++ix) row[ix] = probability.at(ix, iy) > threshold ? 255 : 0;
  }
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8, CV_32S);
  const double cell_area = g.resolution_m * g.resolution_m;
  std::vector<Region> regions;
  for (int label = 1; label < n; ++label) {
    const int count = stats.at<int>(label, cv::CC_STAT_AREA);
    if (count * cell_area < min_area_m2) continue;
    Region r;
    r.cell_count = static_cast<std::size_t>(count);
    r.area_m2 = count * cell_area;
    const int left = stats.at<int>(label, cv::CC_STAT_LEFT), top = stats.at<int>(label, cv::CC_STAT_TOP);
    const int w = stats.at<int>(label, cv::CC_STAT_WIDTH), h = stats.at<int>(label, cv::CC_STAT_HEIGHT);
    cv::Mat own(h + 2, w + 2, CV_8U, cv::Scalar(0));  // one-cell border so contours close
    double sum_p = 0;
    Eigen::Vector2d sum_c = Eigen::Vector2d::Zero();
    for (int iy = top; iy < top + h; ++iy) {
      const int* lrow = labels.ptr<int>(iy);
      for (int ix = left; ix < left + w; ++ix) {
        if (lrow[ix] != label) continue;
        own.at<std::uint8_t>(iy - top + 1, ix - left + 1) = 255;
        r.cells.push_back(iy * g.width_cells + ix);
        sum_p += probability.at(ix, iy);
        sum_c += g.CellCenterInMap(ix, iy);
      }
    }
    r.mean_probability = sum_p / count;
    r.centroid_m = sum_c / count;
    std::vector<std::vector<cv::Point>> contours;
    cv::findContours(own, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
    if (!contours.empty()) {
      const auto& longest = *std::max_element(contours.begin(), contours.end(),
                                              [](const auto& a, const auto& b) { return a.size() < b.size(); });
      for (const cv::Point& p : longest) r.polygon_m.push_back(g.CellCenterInMap(p.x + left - 1, p.y + top - 1));
    }
    regions.push_back(std::move(r));
  }
  std::stable_sort(regions.begin(), regions.end(), [](const Region& a, const Region& b) { return a.cell_count > b.cell_count; });
  for (std::size_t i = 0; i < regions.size(); ++i) regions[i].id = static_cast<int>(i) + 1;
  return regions;
}

MaskGrid RegionMask(const Region& region, const GridGeometry& geometry) {
  MaskGrid mask(geometry, 0);
  for (const int cell : region.cells) mask.cells[cell] = 1;
  return mask;
}

}  // namespace anchordb::engine
