#include "sim/apartment.h"

#include <numbers>
#include <stdexcept>
#include <utility>

#include "sim/apartment_parts.h"

namespace anchordb::sim {
namespace {

using namespace apartment_detail;  // NOLINT: the parts are this file's vocabulary

std::uint64_t SettingSeed(Setting s, std::uint64_t seed) {
  return seed * 0x9E3779B97F4A7C15ULL + static_cast<std::uint64_t>(s) * 0xD1B54A32D192ED03ULL + 1;
}

SettingScene MakeTabletop(Jitter& jitter) {
  Builder b;
  AddRoom(b, false, 0, 0, 0);
  const Eigen::Vector2d table_xy(2.3, 0.0);
  b.AddObject(kFurnitureId, "table", "static");
  AddLeggedTop(b, kFurnitureId, table_xy, Vector3d(0.8, 1.2, 0.03), 0.75, 0.05, 0.05);
  const Vector3d surface(table_xy.x(), table_xy.y(), 0.75);
  AddSmallObjects(b, jitter, surface, {{-0.20, -0.32}, {0.10, -0.08}, {-0.14, 0.30}, {-0.22, 0.02}, {0.22, 0.36}});
  b.AddObject(kDistractorId, "chair", "static");
  AddChair(b, kDistractorId, {2.3, 0.9}, {0.0, 1.0});
  AddPlant(b, kDistractorId + 1, {2.65, -1.25});
  AddPictureOnEastWall(b, kDistractorId + 2, 0.2, 1.55);
  b.AddObject(kDistractorId + 3, "waste_bin", "static");
  b.Cylinder(kDistractorId + 3, Vector3d(1.5, -1.0, 0.175), 0.13, 0.35);

  SettingScene out;
  const Viewpoints views = MakeViewpoints(surface, 15.0 * kDeg, 1.3, 1.3, -35.0 * kDeg);
  out.X_WorldCameraA = views.A;
  out.X_WorldCameraB = views.B;
  out.surface_point_m = surface;
  out.movable_ids = {kCupId, kBoxId, kBookId};
  out.scene = std::move(b.scene());
  return out;
}

SettingScene MakeShelf(Jitter& jitter) {
  Builder b;
  AddRoom(b, false, 0, 0, 0);
  b.AddObject(kFurnitureId, "shelf", "static");
  const double x0 = 2.6, x1 = kRoomHalfX, y_half = 0.5, height = 1.8, panel = 0.02;
  b.BoxMinMax(kFurnitureId, Vector3d(x0, -y_half, 0.0), Vector3d(x1, -y_half + panel, height));
  b.BoxMinMax(kFurnitureId, Vector3d(x0, y_half - panel, 0.0), Vector3d(x1, y_half, height));
  b.BoxMinMax(kFurnitureId, Vector3d(x1 - panel, -y_half + panel, 0.0), Vector3d(x1, y_half - panel, height));
  b.BoxMinMax(kFurnitureId, Vector3d(x0, -y_half + panel, 0.0), Vector3d(x1 - panel, y_half - panel, 0.06));
  for (const double top : {0.08, 0.42, 0.80, 1.20, 1.80}) {
    b.BoxMinMax(kFurnitureId, Vector3d(x0, -y_half + panel, top - panel), Vector3d(x1 - panel, y_half - panel, top));
  }
  const Vector3d surface(0.5 * (x0 + x1 - panel), 0.0, 0.80);
  AddSmallObjects(b, jitter, surface, {{-0.07, -0.37}, {0.05, -0.19}, {-0.05, 0.04}, {-0.08, 0.27}, {0.08, 0.41}});
  b.AddObject(kDistractorId, "row_of_books", "static");
  b.Box(kDistractorId, Vector3d(2.85, -0.15, 0.42 + 0.125), Vector3d(0.22, 0.5, 0.25));
  b.AddObject(kDistractorId + 1, "vase", "static");
  b.Cylinder(kDistractorId + 1, Vector3d(2.8, 0.2, 1.20 + 0.12), 0.06, 0.24);
  AddPlant(b, kDistractorId + 2, {2.7, 1.0});
  AddPictureOnEastWall(b, kDistractorId + 3, -1.1, 1.5);

  SettingScene out;
  const Viewpoints views = MakeViewpoints(surface, 15.0 * kDeg, 1.5, 1.3, -35.0 * kDeg);
  out.X_WorldCameraA = views.A;
  out.X_WorldCameraB = views.B;
  out.surface_point_m = surface;
  out.movable_ids = {kCupId, kBoxId, kBookId};
  out.scene = std::move(b.scene());
  return out;
}

SettingScene MakeArmchair(Jitter& jitter) {
  Builder b;
  AddRoom(b, false, 0, 0, 0);
  b.AddObject(kFurnitureId, "armchair", "static");
  const double ay = 0.6;
  b.BoxMinMax(kFurnitureId, Vector3d(2.1, ay - 0.4, 0.0), Vector3d(2.9, ay + 0.4, 0.42));
  b.BoxMinMax(kFurnitureId, Vector3d(2.7, ay - 0.4, 0.42), Vector3d(2.9, ay + 0.4, 0.95));
  b.BoxMinMax(kFurnitureId, Vector3d(2.1, ay - 0.4, 0.42), Vector3d(2.7, ay - 0.26, 0.64));
  b.BoxMinMax(kFurnitureId, Vector3d(2.1, ay + 0.26, 0.42), Vector3d(2.7, ay + 0.4, 0.64));
  b.AddObject(kFurniture2Id, "small_table", "static");
  const Vector3d surface(2.45, -0.35, 0.55);
  b.Cylinder(kFurniture2Id, Vector3d(surface.x(), surface.y(), 0.535), 0.35, 0.03);
  b.Cylinder(kFurniture2Id, Vector3d(surface.x(), surface.y(), 0.265), 0.04, 0.51);
  b.Cylinder(kFurniture2Id, Vector3d(surface.x(), surface.y(), 0.01), 0.22, 0.02);
  AddSmallObjects(b, jitter, surface, {{-0.17, -0.10}, {0.06, -0.17}, {-0.05, 0.14}, {-0.21, 0.06}, {0.18, 0.12}});
  b.AddObject(kDistractorId, "floor_lamp", "static");
  b.Cylinder(kDistractorId, Vector3d(2.7, -1.3, 0.015), 0.15, 0.03);
  b.Cylinder(kDistractorId, Vector3d(2.7, -1.3, 0.78), 0.015, 1.5);
  b.Cylinder(kDistractorId, Vector3d(2.7, -1.3, 1.6), 0.2, 0.25);
  AddPlant(b, kDistractorId + 1, {2.7, 1.45});
  b.AddObject(kDistractorId + 2, "rug", "static");
  b.BoxMinMax(kDistractorId + 2, Vector3d(1.3, -1.0, 0.0), Vector3d(2.6, 1.1, 0.01));
  AddPictureOnEastWall(b, kDistractorId + 3, 0.0, 1.6);

  SettingScene out;
  const Viewpoints views = MakeViewpoints(surface, 15.0 * kDeg, 1.3, 1.2, -35.0 * kDeg);
  out.X_WorldCameraA = views.A;
  out.X_WorldCameraB = views.B;
  out.surface_point_m = surface;
  out.movable_ids = {kCupId, kBoxId, kBookId};
  out.scene = std::move(b.scene());
  return out;
}

SettingScene MakeDoor(Jitter& jitter) {
  Builder b;
  const double door_y0 = -1.15, door_y1 = -0.25, door_height = 2.05;
  AddRoom(b, true, door_y0, door_y1, door_height);
  b.AddObject(kDistractorId, "corridor", "static");
  b.BoxMinMax(kDistractorId, Vector3d(4.2, -kRoomHalfY - 0.1, 0.0), Vector3d(4.3, kRoomHalfY + 0.1, kWallHeight));
  b.BoxMinMax(kDistractorId, Vector3d(kRoomHalfX + 0.1, kRoomHalfY, 0.0), Vector3d(4.2, kRoomHalfY + 0.1, kWallHeight));
  b.BoxMinMax(kDistractorId, Vector3d(kRoomHalfX + 0.1, -kRoomHalfY - 0.1, 0.0),
              Vector3d(4.2, -kRoomHalfY, kWallHeight));
  // The leaf, hinged at (3.0, door_y0) on the room side, opened 30 deg into the room.
  b.AddObject(kCharacteristicId, "door", "movable");
  b.BoxMinMax(kCharacteristicId, Vector3d(kRoomHalfX, door_y0, 0.01),
              Vector3d(kRoomHalfX + 0.04, door_y1 - 0.02, door_height - 0.02));
  b.Box(kCharacteristicId, Vector3d(kRoomHalfX - 0.03, door_y1 - 0.1, 1.0), Vector3d(0.06, 0.12, 0.02));  // handle
  const Vector3d hinge(kRoomHalfX, door_y0, 0.0);
  const Eigen::Isometry3d open =
      Eigen::Translation3d(hinge) * Eigen::AngleAxisd(30.0 * kDeg, Vector3d::UnitZ()) * Eigen::Translation3d(-hinge);
  MoveObject(b.scene(), kCharacteristicId, open);

  b.AddObject(kFurnitureId, "sideboard", "static");
  b.BoxMinMax(kFurnitureId, Vector3d(2.55, 0.0, 0.0), Vector3d(kRoomHalfX, 1.0, 0.85));
  const Vector3d surface(2.775, 0.5, 0.85);
  AddSmallObjects(b, jitter, surface, {{-0.10, -0.33}, {0.05, -0.14}, {-0.05, 0.10}, {-0.12, 0.31}, {0.12, 0.38}});
  AddPlant(b, kDistractorId + 1, {2.7, 1.5});
  AddPictureOnEastWall(b, kDistractorId + 2, 0.5, 1.55);

  SettingScene out;
  const Viewpoints views = MakeViewpoints(Vector3d(2.8, -0.05, 0.85), 0.0, 1.8, 1.4, 35.0 * kDeg, 0.0);
  out.X_WorldCameraA = views.A;
  out.X_WorldCameraB = views.B;
  out.surface_point_m = surface;
  out.movable_ids = {kCharacteristicId, kCupId, kBoxId, kBookId};
  out.scene = std::move(b.scene());
  return out;
}

SettingScene MakeKitchenLargeObject(Jitter& jitter) {
  Builder b;
  AddRoom(b, false, 0, 0, 0);
  AddKitchen(b, false, 0, 0, 0);
  b.AddObject(kCharacteristicId, "kitchen_chair", "movable");
  AddChair(b, kCharacteristicId, {1.95, -0.8}, {0.0, -1.0});
  const Vector3d surface(2.69, 0.0, 0.9);
  AddSmallObjects(b, jitter, surface, {{-0.14, -0.30}, {0.10, -0.12}, {-0.05, 0.12}, {-0.17, 0.30}, {0.16, 0.33}});
  b.AddObject(kDistractorId, "kettle", "static");
  b.Cylinder(kDistractorId, Vector3d(2.75, -0.95, 0.9 + 0.11), 0.08, 0.22);
  b.AddObject(kDistractorId + 1, "toaster", "static");
  b.Box(kDistractorId + 1, Vector3d(2.8, 0.95, 0.9 + 0.1), Vector3d(0.18, 0.28, 0.2));
  b.AddObject(kDistractorId + 2, "waste_bin", "static");
  b.Cylinder(kDistractorId + 2, Vector3d(2.2, 1.6, 0.2), 0.15, 0.4);

  SettingScene out;
  const Viewpoints views = MakeViewpoints(Vector3d(2.5, -0.2, 0.75), 5.0 * kDeg, 1.6, 1.35, 35.0 * kDeg);
  out.X_WorldCameraA = views.A;
  out.X_WorldCameraB = views.B;
  out.surface_point_m = surface;
  out.movable_ids = {kCharacteristicId, kCupId, kBoxId, kBookId};
  out.scene = std::move(b.scene());
  return out;
}

SettingScene MakeKitchenDrawer(Jitter& jitter) {
  Builder b;
  AddRoom(b, false, 0, 0, 0);
  const double slot_y_half = 0.3, slot_z0 = 0.68, slot_z1 = 0.84;
  AddKitchen(b, true, slot_y_half, slot_z0, slot_z1);
  // The drawer, closed: its front panel stands 2 cm proud of the counter front, its body fills the slot.
  b.AddObject(kCharacteristicId, "drawer", "movable");
  const double front = 2.42, back = 2.92;
  b.BoxMinMax(kCharacteristicId, Vector3d(front - 0.02, -slot_y_half, slot_z0 + 0.005),
              Vector3d(front, slot_y_half, slot_z1 - 0.005));
  b.BoxMinMax(kCharacteristicId, Vector3d(front - 0.05, -0.1, 0.755), Vector3d(front - 0.02, 0.1, 0.775));  // handle
  b.BoxMinMax(kCharacteristicId, Vector3d(front, -slot_y_half + 0.01, slot_z0 + 0.01),
              Vector3d(back, slot_y_half - 0.01, slot_z0 + 0.02));
  b.BoxMinMax(kCharacteristicId, Vector3d(front, -slot_y_half + 0.01, slot_z0 + 0.02),
              Vector3d(back, -slot_y_half + 0.02, slot_z1 - 0.03));
  b.BoxMinMax(kCharacteristicId, Vector3d(front, slot_y_half - 0.02, slot_z0 + 0.02),
              Vector3d(back, slot_y_half - 0.01, slot_z1 - 0.03));
  b.BoxMinMax(kCharacteristicId, Vector3d(back - 0.01, -slot_y_half + 0.02, slot_z0 + 0.02),
              Vector3d(back, slot_y_half - 0.02, slot_z1 - 0.03));
  const Vector3d surface(2.69, 0.0, 0.9);
  AddSmallObjects(b, jitter, surface, {{-0.14, -0.30}, {0.10, -0.12}, {-0.05, 0.12}, {-0.17, 0.30}, {0.16, 0.33}});
  b.AddObject(kDistractorId, "kettle", "static");
  b.Cylinder(kDistractorId, Vector3d(2.75, -0.85, 0.9 + 0.11), 0.08, 0.22);
  b.AddObject(kDistractorId + 1, "fruit_bowl", "static");
  b.Cylinder(kDistractorId + 1, Vector3d(2.78, 0.8, 0.9 + 0.04), 0.12, 0.08);

  SettingScene out;
  const Viewpoints views = MakeViewpoints(Vector3d(2.6, 0.0, 0.82), 15.0 * kDeg, 1.35, 1.35, -35.0 * kDeg);
  out.X_WorldCameraA = views.A;
  out.X_WorldCameraB = views.B;
  out.surface_point_m = surface;
  out.movable_ids = {kCharacteristicId, kCupId, kBoxId, kBookId};
  out.scene = std::move(b.scene());
  return out;
}

SettingScene MakeSofa(Jitter& jitter) {
  Builder b;
  AddRoom(b, false, 0, 0, 0);
  b.AddObject(kFurnitureId, "sofa", "static");
  b.BoxMinMax(kFurnitureId, Vector3d(2.1, -1.0, 0.0), Vector3d(kRoomHalfX, 1.0, 0.42));
  b.BoxMinMax(kFurnitureId, Vector3d(2.78, -1.0, 0.42), Vector3d(kRoomHalfX, 1.0, 0.85));
  b.BoxMinMax(kFurnitureId, Vector3d(2.1, -1.0, 0.42), Vector3d(2.78, -0.85, 0.62));
  b.BoxMinMax(kFurnitureId, Vector3d(2.1, 0.85, 0.42), Vector3d(2.78, 1.0, 0.62));
  // A person lying on the sofa along y, head at +y.
  b.AddObject(kCharacteristicId, "person", "person");
  const Eigen::Matrix3d axis_along_y = Eigen::AngleAxisd(-0.5 * std::numbers::pi, Vector3d::UnitX()).toRotationMatrix();
  const double px = 2.45, seat = 0.42;
  b.Box(kCharacteristicId, Vector3d(px, 0.32, seat + 0.11), Vector3d(0.36, 0.60, 0.22));
  b.Cylinder(kCharacteristicId, Vector3d(px, 0.73, seat + 0.10), 0.10, 0.22, axis_along_y);
  b.Cylinder(kCharacteristicId, Vector3d(px - 0.09, -0.405, seat + 0.075), 0.075, 0.85, axis_along_y);
  b.Cylinder(kCharacteristicId, Vector3d(px + 0.09, -0.405, seat + 0.075), 0.075, 0.85, axis_along_y);
  b.AddObject(kFurniture2Id, "coffee_table", "static");
  AddLeggedTop(b, kFurniture2Id, {1.55, 0.0}, Vector3d(0.6, 1.0, 0.03), 0.45, 0.04, 0.04);
  const Vector3d surface(1.55, 0.0, 0.45);
  AddSmallObjects(b, jitter, surface, {{-0.15, -0.30}, {0.10, -0.12}, {-0.05, 0.12}, {-0.17, 0.32}, {0.17, 0.35}});
  AddPlant(b, kDistractorId, {2.7, 1.5});
  AddPictureOnEastWall(b, kDistractorId + 1, 0.0, 1.5);
  b.AddObject(kDistractorId + 2, "floor_lamp", "static");
  b.Cylinder(kDistractorId + 2, Vector3d(2.7, -1.4, 0.015), 0.15, 0.03);
  b.Cylinder(kDistractorId + 2, Vector3d(2.7, -1.4, 0.78), 0.015, 1.5);
  b.Cylinder(kDistractorId + 2, Vector3d(2.7, -1.4, 1.6), 0.2, 0.25);

  SettingScene out;
  const Viewpoints views = MakeViewpoints(Vector3d(1.9, 0.0, 0.5), 15.0 * kDeg, 1.75, 1.35, -35.0 * kDeg);
  out.X_WorldCameraA = views.A;
  out.X_WorldCameraB = views.B;
  out.surface_point_m = surface;
  out.movable_ids = {kCharacteristicId, kCupId, kBoxId, kBookId};
  out.scene = std::move(b.scene());
  return out;
}

}  // namespace

SettingScene MakeSetting(Setting s, std::uint64_t seed) {
  Jitter jitter(SettingSeed(s, seed));
  SettingScene out;
  switch (s) {
    case Setting::kTA:
      out = MakeTabletop(jitter);
      break;
    case Setting::kSE:
      out = MakeShelf(jitter);
      break;
    case Setting::kCA:
      out = MakeArmchair(jitter);
      break;
    case Setting::kDO:
      out = MakeDoor(jitter);
      break;
    case Setting::kKI1:
      out = MakeKitchenLargeObject(jitter);
      break;
    case Setting::kKI2:
      out = MakeKitchenDrawer(jitter);
      break;
    case Setting::kSO:
      out = MakeSofa(jitter);
      break;
    default:
      throw std::invalid_argument("MakeSetting: unknown setting");
  }
  out.thin_object_id = kThinId;
  out.tall_object_id = kTallId;
  return out;
}

const char* SettingName(Setting s) {
  switch (s) {
    case Setting::kTA:
      return "TA";
    case Setting::kSE:
      return "SE";
    case Setting::kCA:
      return "CA";
    case Setting::kDO:
      return "DO";
    case Setting::kKI1:
      return "KI1";
    case Setting::kKI2:
      return "KI2";
    case Setting::kSO:
      return "SO";
  }
  return "?";
}

std::vector<Setting> AllSettings() {
  return {Setting::kTA, Setting::kSE, Setting::kCA, Setting::kDO, Setting::kKI1, Setting::kKI2, Setting::kSO};
}

PinholeIntrinsics KinectIntrinsics() {
  PinholeIntrinsics K;
  K.width = 640;
  K.height = 480;
  K.fx = 525.0;
  K.fy = 525.0;
  K.cx = 319.5;
  K.cy = 239.5;
  return K;
}

}  // namespace anchordb::sim
