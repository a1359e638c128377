// The orientation prior from the room (issue 17): in the rendered shelf setting (sim/apartment.h, SE) the shelf
// against the east wall gets p(front facing into the room, i.e. towards the viewer) >= 0.7 from the occupancy
// layer; so does a cupboard put against the north wall; a chair faces the table it stands at; a sofa faces the room;
// without a wall within reach the prior stays uniform.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/grounding/orientation_prior.h"
#include "sim/apartment.h"

namespace anchordb::engine::grounding {
namespace grounding_orientation_prior_test {

int Cat(const char* id) { return DefaultKnowledge().categories.IndexOfId(id); }

std::vector<double> Pf(const char* id, double p) {
  const int k = DefaultKnowledge().categories.size();
  std::vector<double> out(static_cast<std::size_t>(k), (1.0 - p) / (k - 1));
  out[static_cast<std::size_t>(Cat(id))] = p;
  return out;
}

// The occupancy layer a robot would project from the scene: a cell is occupied when a static primitive covers its
// centre at 0.3, 0.8 or 1.2 m above the floor (walls, furniture), free otherwise; 5 cm cells.
OccupancyGrid Occupancy(const sim::Scene& scene) {
  GridGeometry g;
  g.resolution_m = 0.05;
  g.origin_x_m = -3.5;
  g.origin_y_m = -3.0;
  g.width_cells = 160;
  g.height_cells = 120;
  OccupancyGrid grid(g, 0);
  for (int iy = 0; iy < g.height_cells; ++iy) {
    for (int ix = 0; ix < g.width_cells; ++ix) {
      const Eigen::Vector2d c = g.CellCenterInMap(ix, iy);
      for (const sim::Primitive& p : scene.primitives) {
        for (const double z : {0.3, 0.8, 1.2}) {
          const Eigen::Vector3d local = p.X_WorldPrim.inverse() * Eigen::Vector3d(c.x(), c.y(), z);
          const bool inside = p.shape == sim::Shape::kBox
                                  ? (local.cwiseAbs() - 0.5 * p.size_m).maxCoeff() <= 0.0
                                  : std::hypot(local.x(), local.y()) <= p.size_m.x() && std::abs(local.z()) <= 0.5 * p.size_m.z();
          if (inside) grid.at(ix, iy) = 100;
        }
      }
    }
  }
  return grid;
}

Viewpoint ViewOf(const Eigen::Isometry3d& X_WorldCamera) {
  const Eigen::Vector3d z = X_WorldCamera.rotation().col(2);  // optical axis
  return {X_WorldCamera.translation().head<2>(), std::atan2(z.y(), z.x())};
}

TEST(GroundingOrientationPriorTest, ShelvesAgainstWallsOfTheRenderedRoomFaceIntoIt) {
  const sim::SettingScene se = sim::MakeSetting(sim::Setting::kSE);
  const OccupancyGrid occupancy = Occupancy(se.scene);
  const Viewpoint view = ViewOf(se.X_WorldCameraA);  // looking east at the shelf
  // The SE shelf spans x 2.6-3.0 m, y -0.5-0.5 m at the east wall; a cupboard stands against the north wall.
  std::vector<FurnitureInput> furniture = {{"shelf", {2.8, 0.0}, {0.4, 1.0}, 0.0, Pf("shelf", 0.7)},
                                           {"cupboard", {0.0, 2.25}, {0.5, 1.0}, M_PI / 2, Pf("cupboard", 0.7)}};
  const RoomLayout room{&occupancy, {}};
  const auto p = RoomOrientationPrior(view, furniture, DefaultKnowledge().categories, room);
  RecordProperty("shelf_front", std::to_string(p[static_cast<std::size_t>(Orientation::kFront)]));
  EXPECT_GE(p[static_cast<std::size_t>(Orientation::kFront)], 0.7);  // front towards the viewer = into the room
  // The cupboard's front faces south (-y); seen from the viewer looking east that is the viewer's right.
  EXPECT_GE(p[kOrientationCount + static_cast<std::size_t>(Orientation::kRight)], 0.7);
  // Without the occupancy layer a wall cannot be found: uniform.
  const auto blind = RoomOrientationPrior(view, furniture, DefaultKnowledge().categories, RoomLayout{});
  for (int o = 0; o < kOrientationCount; ++o) EXPECT_NEAR(blind[static_cast<std::size_t>(o)], 0.25, 1e-12);
  // Far from every wall (the middle of the room) a shelf gets no direction either.
  furniture[0].position_m = {0.0, 0.0};
  const auto middle = RoomOrientationPrior(view, furniture, DefaultKnowledge().categories, room);
  for (int o = 0; o < kOrientationCount; ++o) EXPECT_NEAR(middle[static_cast<std::size_t>(o)], 0.25, 1e-12);
}

TEST(GroundingOrientationPriorTest, AChairFacesItsTableAndASofaFacesTheRoom) {
  const Viewpoint view{{0.0, 0.0}, 0.0};  // looking along +x; +y is the viewer's left
  const std::vector<FurnitureInput> furniture = {
      {"table", {3.0, 0.0}, {0.8, 1.2}, 0.0, Pf("table", 0.8)},
      {"chair", {3.0, 1.0}, {0.5, 0.5}, 0.0, Pf("chair", 0.8)},     // left of the table: faces the viewer's right
      {"sofa", {5.0, 0.0}, {0.9, 2.0}, 0.0, Pf("sofa", 0.8)},       // behind the table: faces the viewer
      {"plant", {3.0, -1.5}, {0.4, 0.4}, 0.0, Pf("plant", 0.9)}};
  const auto p = RoomOrientationPrior(view, furniture, DefaultKnowledge().categories, RoomLayout{});
  const auto at = [&](std::size_t v, Orientation o) { return p[v * kOrientationCount + static_cast<std::size_t>(o)]; };
  EXPECT_GT(at(1, Orientation::kRight), 0.5);
  EXPECT_GT(at(2, Orientation::kFront), 0.5);
  for (int o = 0; o < kOrientationCount; ++o) {
    EXPECT_NEAR(at(0, static_cast<Orientation>(o)), 0.25, 0.02);  // a table has no rule (its p(f) leaks a little)
  }
}

}  // namespace
}  // namespace anchordb::engine::grounding
