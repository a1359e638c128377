// The tree follows the memory (services/octomap/octomap_follow.cc, octomap_keyframe_feed.h) on a real SQLite file:
// with octomap_from_keyframes on, stored keyframes of a rendered room are ray-cast into the map's tree outside the
// scene's write; a 'removed' change event clears its object's voxels (the surface below stays); forgetting decays
// voxels not confirmed since a cutoff. Each is reported.
#include <gtest/gtest.h>

#include "engine/scene/projection.h"
#include "services/capabilities.h"
#include "sim/apartment.h"
#include "sim/renderer.h"
#include "storage/backup.h"
#include "storage/blob_codec.h"
#include "storage/event_repository.h"
#include "storage/octomap_repository.h"
#include "tests/support/temp_dir.h"

namespace anchordb::services {
namespace octomap_follow_test {

class OctomapFollowTest : public ::testing::Test {
 protected:
  static CapabilityOptions Options() {
    CapabilityOptions o;
    o.octomap.from_keyframes = true;
    return o;
  }
  static storage::StoreOptions StoreAt(const std::string& path) {
    storage::StoreOptions so;
    so.path = path;
    return so;
  }
  // Opens a scene at `X_WC`, feeds it three rendered frames and closes it (begin and end keyframes).
  std::int64_t Observe(const sim::Scene& scene, const Eigen::Isometry3d& X_WC, std::uint64_t seed) {
    const PinholeIntrinsics K = sim::KinectIntrinsics();
    OpenSceneRequest open;
    open.camera = K;
    open.X_MapCamera.position_m = X_WC.translation();
    open.X_MapCamera.orientation = Eigen::Quaterniond(X_WC.rotation());
    open.merge = false;
    const std::int64_t id = c.scenes.Open("home", open).id;
    for (int f = 0; f < 3; ++f) {
      const sim::Frame frame = sim::Render(scene, K, X_WC, sim::KindSensor(), seed + f);
      const std::string raw(reinterpret_cast<const char*>(frame.depth_mm.data()), frame.depth_mm.size() * 2);
      FrameInput in;
      in.body = raw;
      in.png = false;
      c.scenes.AddFrame("home", id, in);
    }
    c.scenes.Close("home", id);
    c.octomap_feed.Drain();
    return id;
  }
  std::vector<engine::VoxelState> States(const std::vector<Eigen::Vector3d>& points) {
    std::vector<engine::VoxelState> out;
    for (const auto& q : c.octomap.Query("home", points)) out.push_back(q.state);
    return out;
  }

  testing::TempDir dir;
  storage::Store store{StoreAt(dir.File("follow.sqlite"))};
  Capabilities c{store, Options()};
};

TEST_F(OctomapFollowTest, KeyframesBuildTheTreeAndARemovalClearsItsObjectsVoxels) {
  c.grid.CreateMap({"home", "home"});
  const sim::SettingScene setting = sim::MakeSetting(sim::Setting::kTA, 1);
  const std::int64_t scene_id = Observe(setting.scene, setting.X_WorldCameraA, 10);
  const FollowReport fed = c.octomap_feed.totals();
  EXPECT_EQ(fed.keyframes_integrated, 2u);  // begin and end keyframes
  EXPECT_EQ(c.octomap_feed.failures(), 0u);
  const OctomapInfo info = c.octomap.Get("home");
  EXPECT_GT(info.metadata.occupied_leaves, 1000u);

  // The first movable object on the table: its top is occupied, the air between it and the camera free.
  const int object = setting.movable_ids[0];
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
  for (const sim::Primitive& p : setting.scene.primitives) {
    if (p.object_id != object) continue;
    const Eigen::Vector3d half = p.shape == sim::Shape::kBox ? Eigen::Vector3d(p.size_m / 2)
                                                              : Eigen::Vector3d(p.size_m.x(), p.size_m.x(), p.size_m.z() / 2);
    lo = lo.cwiseMin(p.X_WorldPrim.translation() - half);
    hi = hi.cwiseMax(p.X_WorldPrim.translation() + half);
  }
  const engine::Box3 object_box{lo, hi};
  const std::size_t before = c.octomap.OccupiedVoxels("home", object_box, std::nullopt).voxels.size();
  ASSERT_GT(before, 3u);
  const engine::Box3 table_below{{lo.x(), lo.y(), lo.z() - 0.06}, {hi.x(), hi.y(), lo.z() - 0.001}};
  const std::size_t table_before = c.octomap.OccupiedVoxels("home", table_below, std::nullopt).voxels.size();

  std::int64_t removal_event = 0;
  // Its removal event, with the segment the analysis would store (the object's box).
  store.Write([&](storage::Connection& conn) {
    storage::SegmentRecord s;
    s.map_id = "home";
    s.keyframe_id = c.scenes.Get("home", scene_id).keyframes.at(0).id;
    for (int i = 0; i < 3; ++i) {
      s.min[i] = lo[i];
      s.max[i] = hi[i];
      s.centroid[i] = (lo[i] + hi[i]) / 2;
    }
    s.points = 100;
    const std::vector<float> sample = {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f};
    s.sample = storage::EncodeBlob(storage::BlobElement::kF32, {2, 3}, storage::AsBytes(sample));
    storage::EventRecord e;
    e.map_id = "home";
    e.type = "removed";
    e.detection = "observed";
    e.stamp_ns = 5;
    e.segment_id = storage::InsertSegment(conn, s);
    removal_event = storage::InsertEvent(conn, e);
  });
  const engine::DecodedCloud segment =
      engine::DecodeCloud(c.octomap.EventSegmentCloud("home", removal_event, engine::CloudFormat::kPlyAscii).body, 10);
  ASSERT_EQ(segment.points.size(), 2u);
  EXPECT_FLOAT_EQ(segment.points[1].z(), 0.6f);
  const FollowReport cleared = c.octomap.Follow("home");
  EXPECT_EQ(cleared.removal_events, 1u);
  EXPECT_GT(cleared.voxels_cleared, 0u);
  const engine::Box3 above_bottom{{lo.x(), lo.y(), lo.z() + 0.05}, hi};
  EXPECT_EQ(c.octomap.OccupiedVoxels("home", above_bottom, std::nullopt).voxels.size(), 0u);
  EXPECT_EQ(c.octomap.OccupiedVoxels("home", table_below, std::nullopt).voxels.size(), table_before);
  // Each event counts once.
  EXPECT_EQ(c.octomap.Follow("home").removal_events, 0u);

  // Forgetting: nothing is older than the keyframes' stamps minus a day; everything is older than now + 1 s.
  EXPECT_EQ(c.octomap.ForgetOlderThan("home", 1), 0u);
  const std::size_t forgotten = c.octomap.ForgetOlderThan("home", SystemClock::Instance().NowNs() + 1'000'000'000);
  EXPECT_GT(forgotten, 0u);
  EXPECT_EQ(c.octomap.Get("home").metadata.leaves, 0u);
}

TEST_F(OctomapFollowTest, KeyframeCloudsRoundTripInEveryFormatAndLieOnTheTreesSurfaces) {
  c.grid.CreateMap({"home", "home"});
  const sim::SettingScene setting = sim::MakeSetting(sim::Setting::kTA, 2);
  const std::int64_t scene_id = Observe(setting.scene, setting.X_WorldCameraA, 20);
  const std::int64_t kf = c.scenes.Get("home", scene_id).keyframes.at(0).id;
  const engine::DecodedCloud map_cloud =
      engine::DecodeCloud(c.octomap.KeyframeCloud("home", kf, false, true, engine::CloudFormat::kPcdBinary).body, 1 << 20);
  ASSERT_GT(map_cloud.points.size(), 100000u);
  for (engine::CloudFormat f : {engine::CloudFormat::kPcdAscii, engine::CloudFormat::kPcdBinaryCompressed,
                                engine::CloudFormat::kPlyAscii, engine::CloudFormat::kPlyBinary}) {
    const engine::DecodedCloud other =
        engine::DecodeCloud(c.octomap.KeyframeCloud("home", kf, false, true, f).body, 1 << 20);
    ASSERT_EQ(other.points.size(), map_cloud.points.size()) << static_cast<int>(f);
    for (std::size_t i = 0; i < other.points.size(); i += 997) {
      EXPECT_LT((other.points[i] - map_cloud.points[i]).norm(), 1e-5f) << static_cast<int>(f);
    }
  }
  // The map-frame points are the surfaces the tree holds: nearly all fall in occupied voxels.
  std::vector<Eigen::Vector3d> sample;
  for (std::size_t i = 0; i < map_cloud.points.size(); i += 101) sample.push_back(map_cloud.points[i].cast<double>());
  std::size_t occupied = 0;
  for (const engine::VoxelState s : States(sample)) occupied += s == engine::VoxelState::kOccupied;
  EXPECT_GT(static_cast<double>(occupied) / static_cast<double>(sample.size()), 0.9) << occupied << " of " << sample.size();
  // The camera frame: optical z forward, the same number of points; the background cloud exists too.
  const engine::DecodedCloud camera_cloud =
      engine::DecodeCloud(c.octomap.KeyframeCloud("home", kf, false, false, engine::CloudFormat::kPcdBinary).body, 1 << 20);
  ASSERT_EQ(camera_cloud.points.size(), map_cloud.points.size());
  const Eigen::Isometry3d& X = setting.X_WorldCameraA;
  EXPECT_LT(((X * camera_cloud.points[500].cast<double>()).cast<float>() - map_cloud.points[500]).norm(), 1e-3f);
  EXPECT_GT(engine::DecodeCloud(c.octomap.KeyframeCloud("home", kf, true, true, engine::CloudFormat::kPcdBinary).body,
                                1 << 20).points.size(), 100000u);
  EXPECT_THROW(c.octomap.KeyframeCloud("home", kf + 100, false, true, engine::CloudFormat::kPcdBinary), Error);
}

// octomap_keyframes_per_commit: the feed stores the tree once per N keyframes. A copy of the file taken while keyframes
// are pending is what kill -9 leaves: its stored tree lags, and a server started on it integrates the lagging
// keyframes at start-up into the same tree, byte for byte, as the uninterrupted one. A clean stop stores them.
TEST_F(OctomapFollowTest, KeyframesPendingACommitAreIntegratedAgainAtTheNextStart) {
  ASSERT_EQ(Options().octomap.keyframes_per_commit, 10);  // the default this test relies on
  c.grid.CreateMap({"home", "home"});
  const sim::SettingScene setting = sim::MakeSetting(sim::Setting::kTA, 3);
  Observe(setting.scene, setting.X_WorldCameraA, 30);
  Observe(setting.scene, setting.X_WorldCameraB, 40);
  const OctomapInfo live = c.octomap.Get("home");
  ASSERT_EQ(c.octomap_feed.totals().keyframes_integrated, 4u);
  // The first keyframe created the stored tree; the other three wait for the tenth.
  EXPECT_EQ(live.keyframes_uncommitted, 3);
  const std::optional<storage::OctomapRecord> stored =
      store.Read([](storage::Connection& conn) { return storage::FindOctomap(conn, "home", false); });
  ASSERT_TRUE(stored);
  EXPECT_LT(stored->keyframes_through, live.keyframes_through);
  const std::string uninterrupted_ot = c.octomap.Export("home", TreeFileFormat::kOt).body;

  const std::string crashed = dir.File("crashed.sqlite");
  storage::Backup(dir.File("follow.sqlite"), crashed, 1000);
  {
    storage::Store after(StoreAt(crashed));
    Capabilities restarted{after, Options()};
    EXPECT_EQ(restarted.octomap.Get("home").keyframes_through, stored->keyframes_through);
    restarted.octomap_feed.FollowAtStart({"home"});
    restarted.octomap_feed.Drain();
    EXPECT_EQ(restarted.octomap_feed.totals().keyframes_integrated, 3u);
    const OctomapInfo caught_up = restarted.octomap.Get("home");
    EXPECT_EQ(caught_up.keyframes_through, live.keyframes_through);
    EXPECT_EQ(caught_up.metadata.leaves, live.metadata.leaves);
    EXPECT_TRUE(restarted.octomap.Export("home", TreeFileFormat::kOt).body == uninterrupted_ot);
  }  // a clean stop: the three keyframes are stored
  storage::Store reopened(StoreAt(crashed));
  const std::optional<storage::OctomapRecord> after_stop =
      reopened.Read([](storage::Connection& conn) { return storage::FindOctomap(conn, "home", false); });
  ASSERT_TRUE(after_stop);
  EXPECT_EQ(after_stop->keyframes_through, live.keyframes_through);
}

}  // namespace
}  // namespace anchordb::services
