#pragma once
// A furnished living room for the furniture segmentation evaluation (thesis 5.3.1; issue 16): the room of the
// evaluation settings (inner faces at x = +-3 m, y = +-2.5 m, a door opening in the east wall) with box-built
// furniture of several categories — a sofa, a dining table with a chair, a shelf with boards, a wardrobe, a
// cupboard — each a separate object, their true footprints, and camera poses from which a robot standing in the
// room scans it (a Kinect at 1.3-1.45 m looking down at the pieces, 1.8-2.8 m away). Seeded: piece positions move by
// up to 0.1 m along their wall, headings by up to 4 deg; the same seed gives the same room.
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "sim/renderer.h"

namespace anchordb::sim {

struct PlacedPiece {
  int object_id = 0;
  std::string category;                                 // an id of the grounding knowledge table ("table", "sofa", ...)
  Eigen::Vector2d centre_m = Eigen::Vector2d::Zero();  // true footprint in the world frame
  Eigen::Vector2d extent_m = Eigen::Vector2d::Zero();  // along its own axes
  double yaw_rad = 0.0;
  double height_m = 0.0;
};

struct FurnishedRoom {
  Scene scene;
  std::vector<PlacedPiece> pieces;
  std::vector<Eigen::Isometry3d> X_WorldCamera;  // optical-frame poses of the scanning views
  int table_index = -1;                           // the dining table in `pieces`
  Eigen::Vector3d table_top_m = Eigen::Vector3d::Zero();  // centre of its top surface
};

FurnishedRoom MakeFurnishedRoom(std::uint64_t seed);

}  // namespace anchordb::sim
