// The frame journal over real HTTP (issue 12, acceptance 1): acknowledged frames, then kill -9 of the real binary at
// several points (the first frame; mid-way to a checkpoint; right at and after a checkpoint; right after a settled
// and after a manual keyframe; after a merged first frame). The restarted server must hold every acknowledged frame
// with layers byte-identical to an uninterrupted run fed the same frames (a second server on a fresh database), the
// same keyframes (none made twice), and then answer the rest of the frames exactly as the uninterrupted run did (the
// settle detector continued from the same state).
#include "api/http_api.h"  // Eigen before httplib (see api/http_api.h)
#include "engine/scene/depth_image.h"
#include "sim/apartment.h"
#include "sim/renderer.h"
#include "storage/frame_journal.h"
#include "storage/connection.h"
#include "tests/support/server_process.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>
#include <httplib.h>

#include <nlohmann/json.hpp>

namespace anchordb {
namespace scene_journal_http_test {

using nlohmann::json;

// One step of a client's session with a scene model: a frame, or a manual keyframe.
struct Step {
  bool keyframe = false;
  std::string depth;       // PNG or raw little-endian u16
  bool png = true;
  std::string dynamic;     // mask PNG, empty for none
  std::string query;       // stamp= and depth_scale=
};

// A server on its own database file, restartable.
struct Server {
  explicit Server(std::string db) : db_path(std::move(db)) { Start(); }
  void Start() {
    process = std::make_unique<testing::ServerProcess>(db_path);
    client = std::make_unique<httplib::Client>("127.0.0.1", process->port());
    client->set_read_timeout(60, 0);
  }
  void Kill() {
    client.reset();
    process->Kill();
    process.reset();
  }
  json Post(const std::string& path, const json& body, int expected = 200) {
    auto r = client->Post(path, body.dump(), "application/json");
    EXPECT_TRUE(r && r->status == expected) << path << " " << (r ? r->body : "no response");
    return r ? json::parse(r->body, nullptr, false) : json();
  }
  std::string Get(const std::string& path) {
    auto r = client->Get(path);
    EXPECT_TRUE(r && r->status == 200) << path << " " << (r ? r->body : "no response");
    return r ? r->body : std::string();
  }
  // Sends a step; its answer (every frame is acknowledged, and durable: persisted_frames == frames).
  json Send(const std::string& scene, const Step& s) {
    if (s.keyframe) return Post(scene + "/keyframes", json::object(), 201);
    const std::string path = scene + "/frames?" + s.query;
    const char* type = s.png ? "image/png" : "application/octet-stream";
    httplib::MultipartFormDataItems parts = {{"depth", s.depth, "depth", type}, {"dynamic", s.dynamic, "dynamic.png", "image/png"}};
    httplib::Result r = s.dynamic.empty() ? client->Post(path, s.depth, type) : client->Post(path, parts);
    EXPECT_TRUE(r && r->status == 200) << path << " " << (r ? r->body : "no response");
    const json out = r ? json::parse(r->body, nullptr, false) : json();
    EXPECT_EQ(out.value("persisted_frames", -1), out.value("frames", -2)) << out.dump();
    return out;
  }
  std::int64_t JournalRows() {
    storage::ConnectionOptions o;
    o.read_only = true;
    return storage::CountJournalFrames(*storage::OpenConnection(testing::DatabaseLocation(db_path), o));
  }

  std::string db_path;
  std::unique_ptr<testing::ServerProcess> process;
  std::unique_ptr<httplib::Client> client;
};

// What a client can see of a model: its four layers as raw bytes and its description.
struct Observation {
  std::string static_m, reliability, movable, dynamic;
  json scene;
  bool operator==(const Observation&) const = default;
};

Observation Observe(Server& s, const std::string& scene) {
  Observation o;
  o.static_m = s.Get(scene + "/layers/static?format=raw");
  o.reliability = s.Get(scene + "/layers/reliability?format=raw");
  o.movable = s.Get(scene + "/layers/movable?format=raw");
  o.dynamic = s.Get(scene + "/layers/dynamic?format=raw");
  const json full = json::parse(s.Get(scene), nullptr, false);
  for (const char* key : {"frames", "persisted_frames", "last_frame_ns", "status", "keyframes", "merge", "state"}) {
    if (full.contains(key)) o.scene[key] = full[key];
  }
  if (o.scene.contains("merge")) o.scene["merge"].erase("timing_ms");  // how long the merge took
  return o;
}

json Camera(const PinholeIntrinsics& K) {
  return {{"width", K.width}, {"height", K.height}, {"fx", K.fx}, {"fy", K.fy}, {"cx", K.cx}, {"cy", K.cy}};
}
json PoseJson(const Eigen::Isometry3d& X) {
  const Eigen::Quaterniond q(X.linear());
  return {{"position", {X.translation().x(), X.translation().y(), X.translation().z()}},
          {"orientation", {q.x(), q.y(), q.z(), q.w()}}};
}

// Frame i of a rendered session as PNG, raw, or raw in 1/5 mm (TUM: depth_scale=5000), with a stamp.
Step MakeStep(const sim::Frame& f, const PinholeIntrinsics& K, int i, const std::string& dynamic) {
  Step s;
  s.query = "stamp=" + std::to_string(1'700'000'000'000'000'000LL + i * 33'000'000LL);
  s.dynamic = dynamic;
  if (i % 7 == 5) {
    std::vector<std::uint16_t> fifths(f.depth_mm.size());
    for (std::size_t p = 0; p < fifths.size(); ++p) fifths[p] = static_cast<std::uint16_t>(std::min(65535, f.depth_mm[p] * 5));
    s.depth.assign(reinterpret_cast<const char*>(fifths.data()), fifths.size() * 2);
    s.png = false;
    s.query += "&depth_scale=5000";
  } else if (i % 3 == 2) {
    s.depth.assign(reinterpret_cast<const char*>(f.depth_mm.data()), f.depth_mm.size() * 2);
    s.png = false;
  } else {
    s.depth = engine::EncodeDepthPng(f.depth_mm, K.width, K.height);
  }
  return s;
}

// 40 frames of the tabletop and a manual keyframe after frame 27: a person (a dynamic mask) carries an object 30 cm
// along the table in frames 11-14, then the scene stays still, so the movement settles (a 'settled' keyframe).
std::vector<Step> Session() {
  sim::SettingScene setting = sim::MakeSetting(sim::Setting::kTA, 3);
  const PinholeIntrinsics K = sim::KinectIntrinsics();
  const int object = setting.movable_ids.at(1);
  const int person = 900;
  setting.scene.objects.push_back({person, "person", "person"});
  const Eigen::Vector3d table = setting.surface_point_m;
  const Eigen::Vector3d side = (table - setting.X_WorldCameraA.translation()).cross(Eigen::Vector3d::UnitZ()).normalized();
  sim::Primitive body;
  body.object_id = person;
  body.shape = sim::Shape::kCylinder;
  body.size_m = {0.2, 0.0, 1.7};
  body.X_WorldPrim.translation() = Eigen::Vector3d(table.x(), table.y(), 0.85) + side * 0.75;
  std::vector<Step> steps;
  for (int i = 0; i < 40; ++i) {
    sim::Scene scene = setting.scene;
    if (i >= 10) {
      Eigen::Isometry3d moved = Eigen::Isometry3d::Identity();
      moved.translation() = side * (i < 14 ? 0.1 * (i - 9) : 0.3) + Eigen::Vector3d(0, 0, i < 14 ? 0.2 : 0.0);
      sim::MoveObject(scene, object, moved);
    }
    if (i >= 10 && i < 14) scene.primitives.push_back(body);
    // The kind sensor: the settle detector never settles on the Kinect-v1-like default (issue 13's note).
    const sim::Frame f = sim::Render(scene, K, setting.X_WorldCameraA, sim::KindSensor(), 2000 + i);
    std::string mask;
    if (i >= 10 && i < 14) {
      std::vector<std::uint8_t> m(f.object_id.size());
      for (std::size_t p = 0; p < m.size(); ++p) m[p] = f.object_id[p] == person;
      mask = engine::EncodeMaskPng(m, K.width, K.height);
    }
    steps.push_back(MakeStep(f, K, i, mask));
    if (i == 26) steps.push_back(Step{true, {}, true, {}, {}});
  }
  return steps;
}

json OpenBody() {
  const sim::SettingScene setting = sim::MakeSetting(sim::Setting::kTA, 3);
  return {{"camera", Camera(sim::KinectIntrinsics())}, {"pose", PoseJson(setting.X_WorldCameraA)}, {"stamp", 1'700'000'000'000'000'000LL}};
}

// The answer without what depends on when it was given.
json Comparable(json answer) {
  answer.erase("analysis");  // events carry creation times; their number is compared below
  return answer;
}

class SceneJournalHttpTest : public ::testing::Test {
 protected:
  testing::TempDir dir_;
};

TEST_F(SceneJournalHttpTest, KillNineAfterAnyAcknowledgedFrameLosesNothingAndReplaysIdentically) {
  const std::vector<Step> steps = Session();
  // The uninterrupted run: the answers to every step, and what a client sees after each one.
  Server reference(dir_.File("reference.sqlite"));
  reference.Post("/v1/maps", {{"id", "home"}}, 201);
  const std::string scene = "/v1/maps/home/scenes/" + std::to_string(reference.Post("/v1/maps/home/scenes", OpenBody(), 201)["id"].get<std::int64_t>());
  std::vector<json> answers;
  std::vector<Observation> seen;
  int settled_step = -1, manual_step = -1;
  for (std::size_t k = 0; k < steps.size(); ++k) {
    answers.push_back(reference.Send(scene, steps[k]));
    seen.push_back(Observe(reference, scene));
    if (answers.back().contains("analysis") && settled_step < 0 && k > 0 && !steps[k].keyframe) settled_step = static_cast<int>(k);
    if (steps[k].keyframe) manual_step = static_cast<int>(k);
  }
  // The close waits for its analysis, which runs after every earlier keyframe's (one FIFO per map): the events
  // compared below are complete, not a race with the worker.
  const json closed = reference.Post(scene + ":close?wait_for_analysis=true", json::object());
  const Observation final_seen = Observe(reference, scene);
  const std::string events = reference.Get("/v1/maps/home/events");
  const std::string end_depth = reference.Get("/v1/maps/home/keyframes/" + std::to_string(closed["keyframe"].get<std::int64_t>()) + "/depth");
  ASSERT_EQ(reference.JournalRows(), 0) << "closing a model deletes its journal";
  // The session has what the kill points need: a settled keyframe before the manual one, a checkpoint at 30.
  std::vector<std::string> kinds;
  for (const json& k : final_seen.scene["keyframes"]) kinds.push_back(k["kind"]);
  ASSERT_EQ(kinds, (std::vector<std::string>{"begin", "settled", "manual", "end"}));
  ASSERT_GT(settled_step, 0);
  ASSERT_LT(settled_step, manual_step);
  std::printf("settled keyframe with frame %d, manual keyframe after frame 27, 40 frames\n", settled_step + 1);

  // Kill points, as the number of steps acknowledged (step k < manual_step is frame k + 1).
  const std::vector<int> kill_after = {1, 17, settled_step + 1, settled_step + 2, manual_step + 1, 30 + 1, 31 + 1,
                                       static_cast<int>(steps.size())};
  for (const int acked : kill_after) {
    SCOPED_TRACE("kill -9 after " + std::to_string(acked) + " acknowledged steps");
    Server crashed(dir_.File("crash" + std::to_string(acked) + ".sqlite"));
    crashed.Post("/v1/maps", {{"id", "home"}}, 201);
    crashed.Post("/v1/maps/home/scenes", OpenBody(), 201);
    for (int k = 0; k < acked; ++k) EXPECT_EQ(Comparable(crashed.Send(scene, steps[k])), Comparable(answers[k])) << k;
    crashed.Kill();
    const std::int64_t frames = seen[acked - 1].scene["frames"];
    const std::int64_t checkpoint = frames / 30 * 30;
    EXPECT_EQ(crashed.JournalRows(), frames - checkpoint + (checkpoint > 0 ? 1 : 0))
        << "the journal holds the frames since the checkpoint and the checkpoint's last frame";
    crashed.Start();
    const Observation after = Observe(crashed, scene);
    EXPECT_EQ(after.scene, seen[acked - 1].scene);
    EXPECT_TRUE(after.static_m == seen[acked - 1].static_m && after.reliability == seen[acked - 1].reliability &&
                after.movable == seen[acked - 1].movable && after.dynamic == seen[acked - 1].dynamic)
        << "layers differ from the uninterrupted run's";
    // The rest of the session is answered as in the uninterrupted run (same keyframes at the same frames).
    for (std::size_t k = acked; k < steps.size(); ++k) {
      EXPECT_EQ(Comparable(crashed.Send(scene, steps[k])), Comparable(answers[k])) << k;
    }
    EXPECT_EQ(Comparable(crashed.Post(scene + ":close?wait_for_analysis=true", json::object())), Comparable(closed));
    EXPECT_EQ(crashed.Get("/v1/maps/home/keyframes/" + std::to_string(closed["keyframe"].get<std::int64_t>()) + "/depth"), end_depth)
        << "the end keyframe shows the latest frame";
    EXPECT_TRUE(Observe(crashed, scene) == final_seen);
    EXPECT_EQ(json::parse(crashed.Get("/v1/maps/home/events"))["events"].size(), json::parse(events)["events"].size());
    EXPECT_EQ(crashed.JournalRows(), 0);
  }
}

// A model whose first frame merged an earlier one: the merge is checkpointed with that frame, so the replay after a
// kill does not merge again (the earlier model is superseded once) and the layers equal the uninterrupted run's.
TEST_F(SceneJournalHttpTest, KillNineAfterAMergedFirstFrameReplaysWithoutMergingAgain) {
  const sim::SettingScene setting = sim::MakeSetting(sim::Setting::kTA, 2);
  const PinholeIntrinsics K = sim::KinectIntrinsics();
  std::vector<Step> a, b;
  for (int i = 0; i < 8; ++i) a.push_back(MakeStep(sim::Render(setting.scene, K, setting.X_WorldCameraA, {}, 300 + i), K, 3 * i, {}));
  for (int i = 0; i < 6; ++i) b.push_back(MakeStep(sim::Render(setting.scene, K, setting.X_WorldCameraA, {}, 400 + i), K, i, {}));
  const json open = {{"camera", Camera(K)}, {"pose", PoseJson(setting.X_WorldCameraA)}};
  auto prepare = [&](Server& s) {
    s.Post("/v1/maps", {{"id", "home"}}, 201);
    const std::string first = "/v1/maps/home/scenes/" + std::to_string(s.Post("/v1/maps/home/scenes", open, 201)["id"].get<std::int64_t>());
    for (const Step& step : a) s.Send(first, step);
    s.Post(first + ":close", json::object());
    const json opened = s.Post("/v1/maps/home/scenes", open, 201);
    EXPECT_TRUE(opened["merge"]["pending"].get<bool>()) << opened.dump();
    return "/v1/maps/home/scenes/" + std::to_string(opened["id"].get<std::int64_t>());
  };
  Server reference(dir_.File("reference.sqlite"));
  const std::string scene = prepare(reference);
  std::vector<json> answers;
  for (const Step& step : b) answers.push_back(reference.Send(scene, step));
  const Observation at3 = [&] {
    Server probe(dir_.File("probe.sqlite"));
    const std::string s = prepare(probe);
    for (int k = 0; k < 3; ++k) probe.Send(s, b[k]);
    return Observe(probe, s);
  }();
  const Observation final_seen = Observe(reference, scene);
  for (const int acked : {1, 3}) {
    SCOPED_TRACE("kill -9 after " + std::to_string(acked) + " frames of the merging model");
    Server crashed(dir_.File("crash" + std::to_string(acked) + ".sqlite"));
    ASSERT_EQ(prepare(crashed), scene);
    for (int k = 0; k < acked; ++k) EXPECT_EQ(Comparable(crashed.Send(scene, b[k])), Comparable(answers[k]));
    crashed.Kill();
    crashed.Start();
    if (acked == 3) {
      EXPECT_TRUE(Observe(crashed, scene) == at3);
    }
    EXPECT_TRUE(json::parse(crashed.Get(scene))["merge"]["performed"].get<bool>());
    for (std::size_t k = acked; k < b.size(); ++k) EXPECT_EQ(Comparable(crashed.Send(scene, b[k])), Comparable(answers[k]));
    EXPECT_TRUE(Observe(crashed, scene) == final_seen);
  }
}

}  // namespace
}  // namespace anchordb
