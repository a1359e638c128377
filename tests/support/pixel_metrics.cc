#include "tests/support/pixel_metrics.h"

#include <opencv2/imgproc.hpp>

namespace anchordb::testing {

std::vector<std::uint8_t> TransitionZone(const std::vector<std::uint8_t>& truth, int width, int height, int radius_px) {
  const cv::Mat t(height, width, CV_8U, const_cast<std::uint8_t*>(truth.data()));
  const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * radius_px + 1, 2 * radius_px + 1));
  cv::Mat dilated, eroded;
  cv::dilate(t, dilated, kernel);
  cv::erode(t, eroded, kernel, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  std::vector<std::uint8_t> zone(truth.size());
  for (std::size_t i = 0; i < zone.size(); ++i) zone[i] = (dilated.data[i] != 0) != (eroded.data[i] != 0);
  return zone;
}

PixelCounts CountPixels(const std::vector<std::uint8_t>& movable, const std::vector<std::uint8_t>& truth,
                        const std::vector<std::uint8_t>& zone) {
  PixelCounts c;
  for (std::size_t i = 0; i < movable.size(); ++i) {
    if (!zone.empty() && zone[i]) {
      ++c.ignored;
      continue;
    }
    const bool m = movable[i] != 0, t = truth[i] != 0;
    if (m && t) ++c.tp;
    else if (m) ++c.fp;
    else if (t) ++c.fn;
    else ++c.tn;
  }
  return c;
}

}  // namespace anchordb::testing
