#pragma once
// The evaluation settings of thesis section 3.5.1 / appendix A as synthetic scenes: a room (floor and four walls,
// inner faces at x = +-3 m and y = +-2.5 m, floor top at z = 0, REP-103 world frame, z up) with the furniture of
// the setting against the east wall (+x), small objects on its supporting surface, a few distractor objects that
// never move, and the two camera viewpoints A and B of the cases.
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "schema/types.h"
#include "sim/renderer.h"

namespace anchordb::sim {

// TA tabletop; SE shelf with boards; CA armchair + small table; DO door; KI1 kitchen (a large object, a chair, is
// displaced); KI2 kitchen drawer; SO sofa with a lying person.
enum class Setting { kTA, kSE, kCA, kDO, kKI1, kKI2, kSO };

struct SettingScene {
  Scene scene;  // walls, floor, the furniture of the setting and a few distractor objects
  // Viewpoint A (optical frame in the world): 1.3-1.9 m horizontally from the surface point, camera 1.2-1.4 m
  // above the floor, looking down (17-27 deg) at the furniture like a Kinect on a robot's head.
  Eigen::Isometry3d X_WorldCameraA = Eigen::Isometry3d::Identity();
  // Viewpoint B: the eye 0.45 m from A's, the heading (yaw of the optical axis) turned by 35 deg (31-34 deg between
  // the optical axes), looking down at the same place (which then lies off the image centre, inevitably at these
  // distances, but inside the image).
  Eigen::Isometry3d X_WorldCameraB = Eigen::Isometry3d::Identity();
  // Object ids the cases move. TA, SE, CA: three small objects on the surface (a cup-sized cylinder, a box
  // 15 x 10 x 20 cm, a book). DO, KI1, KI2, SO: the setting's characteristic object first (door leaf, kitchen
  // chair, drawer, lying person), then the same three small objects on the setting's surface.
  std::vector<int> movable_ids;
  int thin_object_id = 0;  // a very thin object on the surface (1 cm high, 10 x 15 cm), for case A2
  int tall_object_id = 0;  // a tall object on the surface (a 30 cm bottle), for case A3
  // A point on the supporting surface (centre of the table top, the shelf board, the small table, ...) [m].
  Eigen::Vector3d surface_point_m = Eigen::Vector3d::Zero();
};

// Builds a setting. `seed` varies the small objects' sizes (+-10 %), positions (+-1.5 cm) and headings slightly;
// same seed, same scene. Furniture, walls and viewpoints do not depend on the seed.
SettingScene MakeSetting(Setting s, std::uint64_t seed = 1);

// Short name of a setting as in the thesis: "TA", "SE", "CA", "DO", "KI1", "KI2", "SO".
const char* SettingName(Setting s);
// All settings, in enum order.
std::vector<Setting> AllSettings();

// Microsoft Kinect (v1) depth camera: 640 x 480, fx = fy = 525, cx = 319.5, cy = 239.5.
PinholeIntrinsics KinectIntrinsics();

}  // namespace anchordb::sim
