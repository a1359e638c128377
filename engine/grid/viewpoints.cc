#include "engine/grid/viewpoints.h"

#include <cmath>
#include <numbers>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <queue>

#include "schema/error.h"

namespace anchordb::engine {
namespace {

cv::Mat ObstacleDistanceCells(const OccupancyGrid& occupancy, const OccupancyThresholds& t) {
  const GridGeometry& g = occupancy.geometry;
  cv::Mat not_obstacle(g.height_cells, g.width_cells, CV_8U);
  for (int iy = 0; iy < g.height_cells; ++iy) {
    auto* row = not_obstacle.ptr<std::uint8_t>(iy);
    for (int ix = 0; ix < g.width_cells; ++ix) row[ix] = IsOccupied(occupancy.at(ix, iy), t) ? 0 : 255;
  }
  cv::Mat distance;
  cv::distanceTransform(not_obstacle, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  return distance;
}

}  // namespace

double PositionScore(double a) {
  // Class-ordered so that every beside viewpoint outranks every in-front one, which outranks every behind one:
  // beside [45, 135] deg -> [0.75, 1] peaking at 90; in front [0, 45) -> [0.4, 0.7); behind (135, 180] -> [0, 0.3).
  const double quarter = std::numbers::pi / 4.0, half = std::numbers::pi / 2.0;
  if (a < quarter) return 0.4 + 0.3 * a / quarter;
  if (a > 3 * quarter) return 0.3 * (std::numbers::pi - a) / quarter;
  return 1.0 - 0.25 * std::abs(a - half) / quarter;
}

std::vector<double> TravelDistances(const OccupancyGrid& occupancy, const OccupancyThresholds& t, int sx, int sy,
                                    double clearance_m) {
  const GridGeometry& g = occupancy.geometry;
  const cv::Mat obstacle_distance = ObstacleDistanceCells(occupancy, t);
  const double clearance_cells = clearance_m / g.resolution_m;
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> dist(g.CellCount(), inf);
  auto passable = [&](int ix, int iy) {
    return IsFree(occupancy.at(ix, iy), t) && obstacle_distance.at<float>(iy, ix) >= clearance_cells;
  };
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  const int start = sy * g.width_cells + sx;
  dist[start] = 0.0;
  open.emplace(0.0, start);
  static constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
  static constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
  const double diag = std::sqrt(2.0) * g.resolution_m;
  while (!open.empty()) {
    const auto [d, index] = open.top();
    open.pop();
    if (d > dist[index]) continue;
    const int ix = index % g.width_cells, iy = index / g.width_cells;
    for (int k = 0; k < 8; ++k) {
      const int nx = ix + kDx[k], ny = iy + kDy[k];
      if (!g.Contains(nx, ny) || !passable(nx, ny)) continue;
      if (k >= 4 && (!passable(ix + kDx[k], iy) || !passable(ix, iy + kDy[k]))) continue;  // no corner cutting
      const double nd = d + (k < 4 ? g.resolution_m : diag);
      const int n = ny * g.width_cells + nx;
      if (nd < dist[n]) dist[n] = nd, open.emplace(nd, n);
    }
  }
  return dist;
}

ViewpointPlan PlanViewpoints(const OccupancyGrid& occupancy, const MaskGrid& surface, const Eigen::Vector2d& robot_m,
                             const Agent& person, const ViewpointOptions& o) {
  const GridGeometry& g = occupancy.geometry;
  if (!(surface.geometry == g)) throw Error(ErrorCode::kUnprocessable, "surface layer and occupancy layer differ in grid");
  const Eigen::Vector2d robot_grid = g.MapToGrid(robot_m);
  const int rx = static_cast<int>(std::floor(robot_grid.x())), ry = static_cast<int>(std::floor(robot_grid.y()));
  if (!g.Contains(rx, ry) || !IsFree(occupancy.at(rx, ry), o.occupancy)) {
    throw Error(ErrorCode::kUnprocessable, "the robot position is not on a known free cell of the occupancy layer", "robot");
  }
  ViewpointPlan plan;
  cv::Mat surface_mat(g.height_cells, g.width_cells, CV_8U);
  Eigen::Vector2d surface_centroid = Eigen::Vector2d::Zero();
  std::size_t surface_count = 0;
  for (int iy = 0; iy < g.height_cells; ++iy) {
    auto* row = surface_mat.ptr<std::uint8_t>(iy);
    for (int ix = 0; ix < g.width_cells; ++ix) {
      row[ix] = surface.at(ix, iy) ? 255 : 0;
      if (row[ix]) surface_centroid += g.CellCenterInMap(ix, iy), ++surface_count;
    }
  }
  if (surface_count == 0) return plan;
  surface_centroid /= static_cast<double>(surface_count);

  // 1. dilate by ~1 m, 2. Sobel -> boundary cells of the dilated area.
  const int r = std::max(1, static_cast<int>(std::lround(o.dilation_radius_m / g.resolution_m)));
  cv::Mat dilated;
  cv::dilate(surface_mat, dilated, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * r + 1, 2 * r + 1)));
  cv::Mat gx, gy;
  cv::Sobel(dilated, gx, CV_16S, 1, 0, 3, 1, 0, cv::BORDER_REPLICATE);
  cv::Sobel(dilated, gy, CV_16S, 0, 1, 3, 1, 0, cv::BORDER_REPLICATE);

  // 3. filters: known free, clearance, distance to surface and person, reachability.
  const cv::Mat obstacle_distance = ObstacleDistanceCells(occupancy, o.occupancy);
  cv::Mat not_surface;
  cv::bitwise_not(surface_mat, not_surface);
  cv::Mat surface_distance;
  cv::distanceTransform(not_surface, surface_distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  const std::vector<double> travel = TravelDistances(occupancy, o.occupancy, rx, ry, o.robot_radius_m);

  std::vector<cv::Point2f> points;
  std::vector<int> point_cells;
  for (int iy = 0; iy < g.height_cells; ++iy) {
    for (int ix = 0; ix < g.width_cells; ++ix) {
      if (!dilated.at<std::uint8_t>(iy, ix)) continue;
      if (gx.at<std::int16_t>(iy, ix) == 0 && gy.at<std::int16_t>(iy, ix) == 0) continue;
      ++plan.boundary_cells;
      if (!IsFree(occupancy.at(ix, iy), o.occupancy)) continue;
      if (obstacle_distance.at<float>(iy, ix) * g.resolution_m < o.min_obstacle_distance_m) continue;
      const double ds = surface_distance.at<float>(iy, ix) * g.resolution_m;
      if (ds < o.min_surface_distance_m || ds > o.max_surface_distance_m) continue;
      const Eigen::Vector2d c = g.CellCenterInMap(ix, iy);
      if ((c - person.position_m).norm() < o.min_person_distance_m) continue;
      if (!std::isfinite(travel[static_cast<std::size_t>(iy) * g.width_cells + ix])) continue;
      points.emplace_back(static_cast<float>(c.x()), static_cast<float>(c.y()));
      point_cells.push_back(iy * g.width_cells + ix);
    }
  }
  plan.candidate_cells = points.size();
  if (points.empty()) return plan;

  // 4. k-means, k proportional to the boundary length.
  const int k = std::clamp(static_cast<int>(std::lround(points.size() * g.resolution_m / o.cluster_spacing_m)), 1,
                           static_cast<int>(points.size()));
  cv::Mat labels, centres;
  cv::theRNG().state = o.seed;
  cv::kmeans(points, k, labels, cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-4), 3,
             cv::KMEANS_PP_CENTERS, centres);
  plan.clusters = k;

  // 5. one representative cell per cluster (the member nearest the centre), rated.
  std::vector<int> best_member(k, -1);
  std::vector<double> best_d(k, std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const int c = labels.at<int>(static_cast<int>(i));
    const double d = std::hypot(points[i].x - centres.at<float>(c, 0), points[i].y - centres.at<float>(c, 1));
    if (d < best_d[c]) best_d[c] = d, best_member[c] = static_cast<int>(i);
  }
  for (int c = 0; c < k; ++c) {
    if (best_member[c] < 0) continue;
    const int cell = point_cells[best_member[c]];
    const int ix = cell % g.width_cells, iy = cell / g.width_cells;
    Viewpoint v;
    v.position_m = g.CellCenterInMap(ix, iy);
    const Eigen::Vector2d to_surface = surface_centroid - v.position_m;
    v.yaw_rad = std::atan2(to_surface.y(), to_surface.x());
    v.travel_distance_m = travel[cell];
    v.surface_distance_m = surface_distance.at<float>(iy, ix) * g.resolution_m;
    const Eigen::Vector2d from_person = v.position_m - person.position_m;
    v.person_distance_m = from_person.norm();
    v.relative_angle_rad = std::abs(std::remainder(std::atan2(from_person.y(), from_person.x()) - person.heading_rad,
                                                   2.0 * std::numbers::pi));
    v.relation = v.relative_angle_rad < std::numbers::pi / 4 ? "in_front"
                 : v.relative_angle_rad > 3 * std::numbers::pi / 4 ? "behind" : "beside";
    v.position_score = PositionScore(v.relative_angle_rad);
    v.travel_score = 1.0 / (1.0 + v.travel_distance_m / o.travel_scale_m);
    v.score = o.weight_position * v.position_score + o.weight_travel * v.travel_score;
    plan.viewpoints.push_back(v);
  }
  std::sort(plan.viewpoints.begin(), plan.viewpoints.end(), [](const Viewpoint& a, const Viewpoint& b) {
    return a.score != b.score ? a.score > b.score : a.travel_distance_m < b.travel_distance_m;
  });
  if (static_cast<int>(plan.viewpoints.size()) > o.max_viewpoints) plan.viewpoints.resize(o.max_viewpoints);
  return plan;
}

int ChooseSurfaceRegion(const std::vector<Region>& regions, const GridGeometry& geometry, const Agent& person,
                        const AttentionOptions& attention, std::optional<int> requested_id) {
  if (regions.empty()) throw Error(ErrorCode::kUnprocessable, "there is no surface region to plan viewpoints around");
  if (requested_id) {
    if (*requested_id < 1 || *requested_id > static_cast<int>(regions.size())) {
      throw Error(ErrorCode::kNotFound, "region " + std::to_string(*requested_id) + " does not exist", "region");
    }
    return *requested_id;
  }
  const AttentionResult result = ComputeAttention(person, regions, geometry, attention);
  return result.attended ? result.attended->region_id : result.relations.front().region_id;
}

}  // namespace anchordb::engine
