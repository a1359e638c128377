#include "tests/eval/segmentation_eval.h"

#include "api/http_api.h"  // Eigen before httplib
#include <httplib.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <sstream>

#include "engine/scene/projection.h"
#include "engine/segmentation/footprint.h"
#include "engine/segmentation/furniture_segmentation.h"
#include "engine/segmentation/geometric_categories.h"
#include "engine/shapes/virtual_scan.h"
#include "sim/apartment.h"
#include "sim/apartment_furnished.h"
#include "sim/lost_key_scenario.h"
#include "sim/renderer.h"
#include "tests/eval/mesh_furniture.h"
#include "tests/support/server_process.h"
#include "tests/support/temp_dir.h"

namespace anchordb::eval {
namespace {

namespace seg = engine::segmentation;

const std::vector<std::string>& CategoryIds() {
  static const std::vector<std::string> ids = {"chair", "armchair", "sofa", "shelf", "wardrobe", "cupboard",
                                               "chest_of_drawers", "table", "plant", "stool"};
  return ids;
}

seg::Footprint Truth(const sim::PlacedPiece& p) {
  seg::Footprint f;
  f.centre_m = p.centre_m;
  f.extent_m = p.extent_m;
  f.yaw_rad = p.yaw_rad;
  return f;
}

void Score(const std::vector<sim::PlacedPiece>& pieces, const std::vector<Eigen::Vector3f>& cloud, SegmentationScore& s,
           const std::string& room_name, const seg::SegmentationParams& params) {
  const auto t0 = std::chrono::steady_clock::now();
  const seg::SegmentationResult r = seg::SegmentFurniture(cloud, params);
  s.bridges_cut += r.bridges_cut;
  s.seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  s.cloud_points.push_back(cloud.size());
  ++s.rooms;
  s.pieces += static_cast<int>(pieces.size());
  s.segments += static_cast<int>(r.segments.size());
  std::vector<bool> found(pieces.size(), false);
  for (const seg::FurnitureSegment& segment : r.segments) {
    int best = -1;
    double best_iou = 0.0;
    for (std::size_t i = 0; i < pieces.size(); ++i) {
      const double iou = seg::FootprintIoU(segment.footprint, Truth(pieces[i]));
      if (iou > best_iou) best_iou = iou, best = static_cast<int>(i);
    }
    std::ostringstream where;
    where << room_name << ": segment at (" << segment.footprint.centre_m.x() << ", " << segment.footprint.centre_m.y() << ") "
          << segment.footprint.extent_m.x() << " x " << segment.footprint.extent_m.y();
    if (best < 0 || best_iou < 0.5) {
      s.misses.push_back(where.str() + " matches no piece (best IoU " + std::to_string(best_iou) + ")");
      continue;
    }
    ++s.right_segments;
    found[static_cast<std::size_t>(best)] = true;
    const std::vector<double> p = seg::GeometricCategories(seg::MeasureSegment(segment, r.floor_z_m), CategoryIds());
    const std::string label = CategoryIds()[static_cast<std::size_t>(std::max_element(p.begin(), p.end()) - p.begin())];
    if (label == pieces[static_cast<std::size_t>(best)].category) ++s.category_right;
    else s.misses.push_back(where.str() + ": " + pieces[static_cast<std::size_t>(best)].category + " called " + label);
  }
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    if (found[i]) s.found_pieces += 1;
    else s.misses.push_back(room_name + ": " + pieces[i].category + " not found");
  }
}

}  // namespace

SegmentationScore EvaluateBoxRooms(int rooms, std::uint64_t seed0, const seg::SegmentationParams& params) {
  SegmentationScore s;
  const PinholeIntrinsics K = sim::KinectIntrinsics();
  for (int k = 0; k < rooms; ++k) {
    const std::uint64_t seed = seed0 + static_cast<std::uint64_t>(k);
    const sim::FurnishedRoom room = sim::MakeFurnishedRoom(seed);
    std::vector<Eigen::Vector3f> cloud;
    for (std::size_t v = 0; v < room.X_WorldCamera.size(); ++v) {
      sim::Frame f = sim::Render(room.scene, K, room.X_WorldCamera[v], sim::SensorModel{}, seed * 31 + v);
      for (auto& d : f.depth_mm) {
        if (d > 3500) d = 0;
      }
      const auto points = engine::BackProjectRaw(f.depth_mm, 1000.0, K, room.X_WorldCamera[v]);
      cloud.insert(cloud.end(), points.begin(), points.end());
    }
    Score(room.pieces, cloud, s, "box room " + std::to_string(seed), params);
  }
  return s;
}

std::optional<SegmentationScore> EvaluateMeshRooms(int rooms, std::uint64_t seed0, const std::string& dir,
                                                   const seg::SegmentationParams& params) {
  // The box room's places, each piece replaced by a mesh of its category (the wardrobe by the Wardrobe mesh of the
  // 'cupboard' folder: the grounding table has a wardrobe category).
  struct Choice {
    std::string file, category;
  };
  const std::vector<Choice> choice = {{"sofa/Sofa_01.obj", "sofa"}, {"table/KitchenTable_01.obj", "table"},
                                      {"chair/ChairA_01.obj", "chair"}, {"shelf/ShoeRack_01.obj", "shelf"},
                                      {"cupboard/Wardrobe_01.obj", "wardrobe"}, {"cupboard/TVCabinet_01.obj", "cupboard"}};
  std::vector<engine::TriangleMesh> meshes;
  for (const Choice& c : choice) {
    auto mesh = ReadObjFile(dir + "/" + c.file);
    if (!mesh) return std::nullopt;
    meshes.push_back(std::move(*mesh));
  }
  SegmentationScore s;
  const PinholeIntrinsics K = sim::KinectIntrinsics();
  const engine::ScanCamera cam = ScanCameraOf(K);
  for (int k = 0; k < rooms; ++k) {
    const std::uint64_t seed = seed0 + static_cast<std::uint64_t>(k);
    sim::FurnishedRoom room = sim::MakeFurnishedRoom(seed);
    for (const sim::PlacedPiece& p : room.pieces) sim::RemoveObject(room.scene, p.object_id);
    // Each mesh: its bounding box's footprint centred on the piece's place, its longer side along the piece's.
    std::vector<sim::PlacedPiece> pieces;
    std::vector<PlacedMesh> placed;
    for (std::size_t i = 0; i < meshes.size(); ++i) {
      const MeshBounds b = Bounds(meshes[i]);
      const sim::PlacedPiece& place = room.pieces[i];
      const Eigen::Vector3f size = b.hi - b.lo;
      const bool turn = size.y() > size.x();  // the mesh's longer side to the piece's own x
      // Keep a piece against its wall: move it so that its depth ends where the box piece's did. Which way the
      // piece's wall lies along its own y: sofa and shelf +y, wardrobe and cupboard -y, table and chair stand free
      // (sim/apartment_furnished.cc).
      constexpr double kWallSide[] = {1.0, 0.0, 0.0, 1.0, -1.0, -1.0};
      const MeshFit fit = FitMesh(b, turn ? -1 : 0, place.centre_m, place.yaw_rad, place.extent_m.y(), kWallSide[i]);
      placed.push_back({&meshes[i], fit.X_WorldMesh});
      sim::PlacedPiece p = place;
      p.category = choice[i].category;
      p.centre_m = fit.centre_m;
      p.extent_m = fit.extent_m;
      p.height_m = fit.height_m;
      pieces.push_back(p);
    }
    std::vector<Eigen::Vector3f> cloud;
    std::mt19937_64 rng(seed * 977 + 5);
    std::normal_distribution<double> normal(0.0, 1.0);
    for (std::size_t v = 0; v < room.X_WorldCamera.size(); ++v) {
      const sim::Frame f = sim::Render(room.scene, K, room.X_WorldCamera[v], sim::SensorModel{}, seed * 31 + v);
      std::vector<std::uint16_t> depth = f.depth_mm;
      std::vector<double> nearest(f.true_depth_m.begin(), f.true_depth_m.end());  // z-buffer: the room's true depth
      ZBufferMeshes(placed, cam, room.X_WorldCamera[v], 0.5, nearest, [&](std::size_t px, double d) {
        // Axial noise of the sim's sensor (Nguyen et al. 2012), white.
        const double z = d + normal(rng) * (0.0012 + 0.0019 * (d - 0.4) * (d - 0.4));
        depth[px] = static_cast<std::uint16_t>(std::lround(z * 1000.0));
      });
      for (auto& dd : depth) {
        if (dd > 3500) dd = 0;
      }
      const auto points = engine::BackProjectRaw(depth, 1000.0, K, room.X_WorldCamera[v]);
      cloud.insert(cloud.end(), points.begin(), points.end());
    }
    Score(pieces, cloud, s, "mesh room " + std::to_string(seed), params);
  }
  return s;
}

LostKeyScore EvaluateLostKey(int runs, std::uint64_t seed0, std::optional<double> core_density) {
  LostKeyScore out;
  for (int k = 0; k < runs; ++k) {
    testing::TempDir dir;
    testing::ServerProcess server(dir.File("lostkey.sqlite"));
    httplib::Client client("127.0.0.1", server.port());
    client.set_read_timeout(120, 0);
    sim::LostKeyOptions o;
    o.seed = seed0 + static_cast<std::uint64_t>(k);
    o.enter_furniture = false;
    o.segment_furniture = true;
    if (core_density) o.segmentation_params = {{"core_density", *core_density}};
    const sim::LostKeyResult r = sim::RunLostKeyScenario(client, o);
    ++out.runs;
    const std::string sentence = r.where.value("sentence", std::string());
    out.sentences.push_back(sentence);
    std::ostringstream pieces;
    for (const nlohmann::json& seg : r.segmentation["result"].value("segments", nlohmann::json::array())) {
      pieces << seg["label"].get<std::string>() << " " << seg["label_probability"].get<double>() << " at (" << seg["position_m"][0]
             << ", " << seg["position_m"][1] << ") " << seg["extent_m"][0] << " x " << seg["extent_m"][1] << " h "
             << seg["height_m"] << "; ";
    }
    out.segments.push_back(pieces.str());
    const nlohmann::json placement = r.where.value("placement", nlohmann::json());
    if (!placement.is_object() || !placement.contains("furniture_instance") || placement["furniture_instance"].is_null()) continue;
    const auto piece = client.Get("/v1/maps/home/furniture/" + std::to_string(placement["furniture_instance"].get<std::int64_t>()));
    if (!piece || piece->status != 200) continue;
    const nlohmann::json p = nlohmann::json::parse(piece->body);
    if (const char* dump = std::getenv("SEGMENTATION_EVAL_DUMP")) {  // the answer's piece as PCD, for inspection
      const auto cloud = client.Get("/v1/maps/home/furniture/" + std::to_string(placement["furniture_instance"].get<std::int64_t>()) + "/cloud?format=pcd_ascii");
      if (cloud && cloud->status == 200) std::ofstream(std::string(dump) + "/lost_key_" + std::to_string(o.seed) + ".pcd") << cloud->body;
    }
    seg::Footprint found, truth;
    found.centre_m = Eigen::Vector2d(p["position_m"][0], p["position_m"][1]);
    found.extent_m = Eigen::Vector2d(p["extent_m"][0], p["extent_m"][1]);
    found.yaw_rad = p["yaw_rad"];
    truth.centre_m = r.table_centre_m;
    truth.extent_m = r.table_extent_m;
    const bool is_table = p["perceived"].get<bool>() && seg::FootprintIoU(found, truth) >= 0.5;
    out.segmented_table += is_table;
    if (is_table && placement.value("name", std::string()) == "table" && sentence.find("table") != std::string::npos) ++out.named_table;
  }
  return out;
}

}  // namespace anchordb::eval
