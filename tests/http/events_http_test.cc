// Change events, the lost-key rule, past-time where-is, operator edits, re-analysis of old keyframes and bad input,
// over real HTTP on loopback (the anchordb binary, a SQLite file) with rendered depth frames.
#include "api/http_api.h"  // Eigen before httplib (see api/http_api.h)
#include "sim/apartment.h"
#include "sim/lost_key_scenario.h"
#include "sim/renderer.h"
#include "tests/support/server_process.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>
#include <httplib.h>

#include <nlohmann/json.hpp>

#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <regex>
#include <set>

namespace anchordb {
namespace events_http_test {

using nlohmann::json;

// `anchordb token create --role <role> --db <db>`; returns the printed secret ("" when it failed).
std::string CreateToken(const std::string& db, const std::string& role) {
  const std::string bin = testing::AnchordbBin();
  FILE* pipe = popen((std::string(bin) + " token create --role " + role + " --db '" + testing::DatabaseLocation(db) + "' 2>&1").c_str(), "r");
  if (!pipe) return "";
  std::string out;
  char buffer[1024];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof(buffer), pipe)) > 0;) out.append(buffer, n);
  pclose(pipe);
  std::smatch m;
  return std::regex_search(out, m, std::regex(R"(\): (\S+))")) ? m[1].str() : "";
}

class EventsHttpTest : public ::testing::Test {
 protected:
  void SetUp() override {
    server_ = std::make_unique<testing::ServerProcess>(dir_.File("events.sqlite"));
    client_ = std::make_unique<httplib::Client>("127.0.0.1", server_->port());
    client_->set_read_timeout(60, 0);
  }
  std::pair<int, json> Call(const std::string& method, const std::string& path, const std::string& body = "{}") {
    httplib::Result r = method == "GET" ? client_->Get(path) : method == "DELETE" ? client_->Delete(path)
                                                                : client_->Post(path, body, "application/json");
    EXPECT_TRUE(r) << method << " " << path;
    if (!r) return {0, json()};
    return {r->status, json::parse(r->body, nullptr, false)};
  }
  json Ok(const std::string& method, const std::string& path, const std::string& body = "{}", int status = 200) {
    auto [code, j] = Call(method, path, body);
    EXPECT_EQ(code, status) << method << " " << path << " " << j.dump();
    return j;
  }

  testing::TempDir dir_;
  std::unique_ptr<testing::ServerProcess> server_;
  std::unique_ptr<httplib::Client> client_;
};

TEST_F(EventsHttpTest, LostKeyMoveIsInferredPastStateAnsweredAndOperatorRelabelSurvivesLaterProcessing) {
  sim::LostKeyOptions o;
  // The kind sensor: on the Kinect-v1-like default the settle detector (engine/scene/settle.h) never settles on a
  // static scene (100-960 movable resets per frame), so the first visit has no settled keyframe. Open (issue 13).
  o.kind_sensor = true;
  o.seed = 10;
  const sim::LostKeyResult result = sim::RunLostKeyScenario(*client_, o);
  // The move inference: the labelled removal at B continued by the observed addition at A.
  const json* moved = nullptr;
  for (const json& e : result.events) if (e["type"] == "moved") moved = &e;
  ASSERT_NE(moved, nullptr) << result.events.dump(1);
  EXPECT_EQ((*moved)["label"], "keys");
  EXPECT_NE((*moved)["explanation"].get<std::string>().find("lost-key rule"), std::string::npos);
  const std::int64_t keys = (*moved)["instance"].get<std::int64_t>();
  // Where now: on the table at A, with evidence keyframes that exist.
  ASSERT_TRUE(result.where.value("present", false)) << result.where.dump();
  EXPECT_NE(result.where["sentence"].get<std::string>().find("on the table"), std::string::npos) << result.where.dump();
  const auto p = result.where["position_m"];
  EXPECT_LT((Eigen::Vector3d(p[0], p[1], p[2]) - result.keys_true_m).norm(), 0.15);
  ASSERT_FALSE(result.where["evidence"].empty());
  for (const json& k : result.where["evidence"]) Ok("GET", "/v1/maps/home/keyframes/" + std::to_string(k["keyframe"].get<std::int64_t>()));
  // Where at a time between taking and bringing: last seen on the shelf, gone.
  EXPECT_FALSE(result.past_where.value("present", true)) << result.past_where.dump();
  EXPECT_NE(result.past_where["sentence"].get<std::string>().find("shelf"), std::string::npos);
  // With a furniture graph of the place, the sentence uses the grounding model's furniture and preferred words.
  const json graph = Ok("POST", "/v1/maps/home/furniture-graphs", json({
      {"viewpoint", {{"position", {0.6, 0.0}}, {"heading_rad", 0.0}}},
      {"furniture", {{{"id", "t"}, {"position", {2.3, 0.0}}, {"extent", {0.8, 1.2}}, {"categories", {{"table", 0.8}, {"chair", 0.2}}}},
                     {{"id", "c"}, {"position", {2.3, 0.9}}, {"extent", {0.45, 0.45}}, {"categories", {{"chair", 0.8}, {"table", 0.2}}}}}}}).dump(), 201);
  const json placed = Ok("GET", "/v1/maps/home/where?label=keys");
  EXPECT_EQ(placed["placement"]["graph"], graph["id"]);
  EXPECT_EQ(placed["placement"]["relation"], "on");
  EXPECT_EQ(placed["sentence"], "The keys are on the table.");
  Ok("POST", "/v1/maps/home/instances", R"({"kind":"object","label":"cup","position":[2.3,1.5,0.0]})", 201);
  const json cup = Ok("GET", "/v1/maps/home/where?label=cup");
  EXPECT_EQ(cup["placement"]["furniture"], "c");  // nearest: the chair
  EXPECT_NE(cup["placement"]["frame"], nullptr);  // relative or intrinsic, as the listener model prefers
  EXPECT_NE(cup["sentence"].get<std::string>().find("the chair"), std::string::npos) << cup.dump();

  // Layered action model: the first visit's keyframes are begin, settled (the movable layer settled after the
  // object was put down: a completed action) and end; the addition belongs to layer 0, which the settled keyframe
  // closed, and the last layer saw nothing change.
  const json first_scene = Ok("GET", "/v1/maps/home/scenes/1");
  std::vector<std::string> kinds;
  for (const json& k : first_scene["keyframes"]) kinds.push_back(k["kind"]);
  EXPECT_EQ(kinds, (std::vector<std::string>{"begin", "settled", "end"}));
  const json first_events = Ok("GET", "/v1/maps/home/events?scene=1")["events"];
  ASSERT_EQ(first_events.size(), 1u);
  EXPECT_EQ(first_events[0]["action_layer"], 0);
  // History: present at B, absent from B, present at A.
  const json history = Ok("GET", "/v1/maps/home/instances/" + std::to_string(keys) + "/history")["history"];
  ASSERT_GE(history.size(), 3u);
  EXPECT_TRUE(history.back()["present"].get<bool>());

  // An operator relabels; dialog may not change it, and a later visit with new events leaves it alone.
  Ok("POST", "/v1/maps/home/instances/" + std::to_string(keys) + ":label", R"({"label":"Car  Keys","source":"operator"})");
  auto [status, refused] = Call("POST", "/v1/maps/home/instances/" + std::to_string(keys) + ":label", R"({"label":"wallet"})");
  EXPECT_EQ(status, 409) << refused.dump();
  sim::LostKeyOptions again = o;
  again.seed = 11;
  again.map = "home";
  again.create_map = false;
  again.start_ns = o.start_ns + 3'600'000'000'000LL;
  sim::RunLostKeyScenario(*client_, again);  // more events in the same map, another labelled removal and move
  const json instance = Ok("GET", "/v1/maps/home/instances/" + std::to_string(keys));
  EXPECT_EQ(instance["labels"], json({{"car keys", 1.0}}));
  EXPECT_TRUE(instance["label_locked"].get<bool>());
  const json where = Ok("GET", "/v1/maps/home/where?label=car%20keys");
  EXPECT_EQ(where["instance"], keys);

  // An operator deletes an instance: it stays deleted.
  Ok("DELETE", "/v1/maps/home/instances/" + std::to_string(keys));
  EXPECT_EQ(Ok("GET", "/v1/maps/home/instances/" + std::to_string(keys))["status"], "deleted");
  EXPECT_EQ(Call("POST", "/v1/maps/home/instances/" + std::to_string(keys) + ":label", R"({"label":"keys"})").first, 409);

  // The audit trail (auth off: actor "loopback"): the dialog's event labels, the operator's relabel and its refusal,
  // the deletion, each with the record before and after; none of the robot's frames.
  const json events = Ok("GET", "/v1/audit?map=home&action=event.label")["entries"];
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events[0]["actor"], json({{"token", "loopback"}, {"role", nullptr}}));
  EXPECT_EQ(events[0]["status"], 200);
  EXPECT_TRUE(events[0]["before"].is_object() && events[0]["after"].is_object()) << events[0].dump();
  const json relabels = Ok("GET", "/v1/audit?map=home&action=instance.label&limit=1000")["entries"];
  bool operator_relabel = false, refusal = false;
  for (const json& e : relabels) {
    if (e["resource"] != "instance=" + std::to_string(keys)) continue;
    if (e["status"] == 200 && e["after"]["labels"] == json({{"car keys", 1.0}}) && e["before"]["labels"] != e["after"]["labels"]) {
      operator_relabel = true;
    }
    if (e["status"] == 409 && e["before"] == e["after"]) refusal = true;
  }
  EXPECT_TRUE(operator_relabel) << relabels.dump();
  EXPECT_TRUE(refusal) << relabels.dump();
  const json deleted = Ok("GET", "/v1/audit?map=home&action=instance.delete")["entries"];
  ASSERT_EQ(deleted.size(), 1u);
  EXPECT_EQ(deleted[0]["after"]["status"], "deleted");
  const json all = Ok("GET", "/v1/audit?map=home&limit=1000")["entries"];
  for (const json& e : all) EXPECT_EQ(e["action"].get<std::string>().find("frames"), std::string::npos) << e.dump();
}

TEST_F(EventsHttpTest, ReanalysisOfAnOldKeyframeFindsAnObjectThatWasBackgroundThen) {
  Ok("POST", "/v1/maps", R"({"id":"home","name":"flat"})", 201);
  sim::SettingScene s = sim::MakeSetting(sim::Setting::kTA, 4);
  const PinholeIntrinsics K = sim::KinectIntrinsics();
  const int box = s.movable_ids.at(1);
  const Eigen::Vector3d box_centre = [&] {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    int n = 0;
    for (const auto& prim : s.scene.primitives) if (prim.object_id == box) c += prim.X_WorldPrim.translation(), ++n;
    return Eigen::Vector3d(c / n);
  }();
  const Eigen::Quaterniond q(s.X_WorldCameraA.linear());
  const json pose = {{"position", {s.X_WorldCameraA.translation().x(), s.X_WorldCameraA.translation().y(), s.X_WorldCameraA.translation().z()}},
                     {"orientation", {q.x(), q.y(), q.z(), q.w()}}};
  const json camera = {{"width", K.width}, {"height", K.height}, {"fx", K.fx}, {"fy", K.fy}, {"cx", K.cx}, {"cy", K.cy}};
  std::int64_t first_begin = 0;
  for (int visit = 0; visit < 2; ++visit) {
    sim::Scene scene = s.scene;
    if (visit == 1) sim::RemoveObject(scene, box);  // gone before the second visit: nobody saw it go
    const json opened = Ok("POST", "/v1/maps/home/scenes",
                           json({{"camera", camera}, {"pose", pose}, {"stamp", 1'000'000'000'000LL * (visit + 1)}}).dump(), 201);
    const std::string base = "/v1/maps/home/scenes/" + std::to_string(opened["id"].get<std::int64_t>());
    for (int i = 0; i < 6; ++i) {
      const sim::Frame f = sim::Render(scene, K, s.X_WorldCameraA, sim::SensorModel{}, 77 + visit * 10 + i);
      auto r = client_->Post(base + "/frames?stamp=" + std::to_string(1'000'000'000'000LL * (visit + 1) + i * 33'000'000LL),
                             std::string(reinterpret_cast<const char*>(f.depth_mm.data()), f.depth_mm.size() * 2), "application/octet-stream");
      ASSERT_TRUE(r && r->status == 200) << (r ? r->body : "");
      if (visit == 0 && i == 0) first_begin = json::parse(r->body)["keyframe"].get<std::int64_t>();
    }
    Ok("POST", base + ":close?wait_for_analysis=true");  // its analysis written before the checks below
  }
  // Nothing was seen to change: no events yet.
  EXPECT_TRUE(Ok("GET", "/v1/maps/home/events")["events"].empty());
  const json re = Ok("POST", "/v1/maps/home/keyframes/" + std::to_string(first_begin) + ":reanalyse");
  bool found = false;
  for (const json& e : re["events"]) {
    if (e["type"] != "removed") continue;
    const auto c = e["details"]["segment"]["centroid_m"];
    found = found || (Eigen::Vector3d(c[0], c[1], c[2]) - box_centre).norm() < 0.12;
    EXPECT_EQ(e["detection"], "reanalysis");
  }
  EXPECT_TRUE(found) << re.dump(1);
  EXPECT_FALSE(Ok("GET", "/v1/maps/home/events?type=removed")["events"].empty());
}

// Two visits of one place; the box went between them unseen, and re-analysing the first visit's begin keyframe against
// the second visit's background finds it removed (as in the test above). Returns that keyframe's id.
std::int64_t TwoVisitsWithAnUnseenRemoval(httplib::Client& client) {
  sim::SettingScene s = sim::MakeSetting(sim::Setting::kTA, 4);
  const PinholeIntrinsics K = sim::KinectIntrinsics();
  const Eigen::Quaterniond q(s.X_WorldCameraA.linear());
  const json pose = {{"position", {s.X_WorldCameraA.translation().x(), s.X_WorldCameraA.translation().y(), s.X_WorldCameraA.translation().z()}},
                     {"orientation", {q.x(), q.y(), q.z(), q.w()}}};
  const json camera = {{"width", K.width}, {"height", K.height}, {"fx", K.fx}, {"fy", K.fy}, {"cx", K.cx}, {"cy", K.cy}};
  std::int64_t first_begin = 0;
  for (int visit = 0; visit < 2; ++visit) {
    sim::Scene scene = s.scene;
    if (visit == 1) sim::RemoveObject(scene, s.movable_ids.at(1));
    auto opened = client.Post("/v1/maps/home/scenes",
                              json({{"camera", camera}, {"pose", pose}, {"stamp", 1'000'000'000'000LL * (visit + 1)}}).dump(), "application/json");
    EXPECT_TRUE(opened && opened->status == 201) << (opened ? opened->body : "");
    if (!opened || opened->status != 201) return 0;
    const std::string base = "/v1/maps/home/scenes/" + std::to_string(json::parse(opened->body)["id"].get<std::int64_t>());
    for (int i = 0; i < 6; ++i) {
      const sim::Frame f = sim::Render(scene, K, s.X_WorldCameraA, sim::SensorModel{}, 77 + visit * 10 + i);
      auto r = client.Post(base + "/frames?stamp=" + std::to_string(1'000'000'000'000LL * (visit + 1) + i * 33'000'000LL),
                           std::string(reinterpret_cast<const char*>(f.depth_mm.data()), f.depth_mm.size() * 2), "application/octet-stream");
      EXPECT_TRUE(r && r->status == 200) << (r ? r->body : "");
      if (r && visit == 0 && i == 0) first_begin = json::parse(r->body)["keyframe"].get<std::int64_t>();
    }
    auto closed = client.Post(base + ":close?wait_for_analysis=true", "{}", "application/json");
    EXPECT_TRUE(closed && closed->status == 200);
  }
  return first_begin;
}

TEST_F(EventsHttpTest, OperatorDeletesAWrongEventAuditedReadersRefusedBadInputChangesNothing) {
  const std::string db = dir_.File("events.sqlite");
  server_->Stop();
  const std::string admin = CreateToken(db, "admin"), reader = CreateToken(db, "reader");
  ASSERT_FALSE(admin.empty());
  ASSERT_FALSE(reader.empty());
  server_ = std::make_unique<testing::ServerProcess>(db, std::vector<std::string>{"--auth=required"});
  client_ = std::make_unique<httplib::Client>("127.0.0.1", server_->port());
  client_->set_read_timeout(60, 0);
  client_->set_bearer_token_auth(admin);
  Ok("POST", "/v1/maps", R"({"id":"home","name":"flat"})", 201);
  const std::int64_t keyframe = TwoVisitsWithAnUnseenRemoval(*client_);
  ASSERT_GT(keyframe, 0);
  const json re = Ok("POST", "/v1/maps/home/keyframes/" + std::to_string(keyframe) + ":reanalyse");
  ASSERT_FALSE(re["events"].empty()) << re.dump(1);
  const json wrong = re["events"][0];
  const std::int64_t id = wrong["id"].get<std::int64_t>();
  const std::string path = "/v1/maps/home/events/" + std::to_string(id);
  ASSERT_FALSE(wrong["evidence"].empty());
  const auto state = [&] {
    json s = {{"events", Ok("GET", "/v1/maps/home/events?limit=1000")["events"]}, {"instances", json::array()}};
    std::set<std::int64_t> instances;  // those the events name (the listing leaves absent ones out)
    for (const json& e : re["events"]) if (e["instance"].is_number()) instances.insert(e["instance"].get<std::int64_t>());
    for (const std::int64_t i : instances) s["instances"].push_back(Ok("GET", "/v1/maps/home/instances/" + std::to_string(i) + "/history"));
    return s;
  };
  const json before = state();

  // Refused without changing anything: a reader's forged delete (403), unknown events and maps (404).
  httplib::Client as_reader("127.0.0.1", server_->port());
  as_reader.set_bearer_token_auth(reader);
  auto forged = as_reader.Delete(path);
  ASSERT_TRUE(forged);
  EXPECT_EQ(forged->status, 403) << forged->body;
  EXPECT_EQ(json::parse(forged->body)["error"]["code"], "forbidden") << forged->body;
  EXPECT_EQ(as_reader.Get(path)->status, 200);  // a reader still reads it
  const struct {
    std::string path;
    int status;
    std::string field;
  } bad[] = {{"/v1/maps/home/events/999999", 404, "event"}, {"/v1/maps/home/events/abc", 404, "event"},
             {"/v1/maps/home/events/-1", 404, "event"}, {"/v1/maps/nowhere/events/" + std::to_string(id), 404, "map"}};
  for (const auto& b : bad) {
    auto [status, body] = Call("DELETE", b.path);
    EXPECT_EQ(status, b.status) << b.path << " " << body.dump();
    EXPECT_EQ(body["error"].value("field", ""), b.field) << b.path << " " << body.dump();
  }
  EXPECT_EQ(state(), before);

  // The admin deletes it: the answer is the event as it was; it is gone from the listing, its evidence keyframes
  // stay, and no instance history names it any more.
  const json deleted = Ok("DELETE", path);
  EXPECT_EQ(deleted, wrong);
  EXPECT_EQ(Call("GET", path).first, 404);
  EXPECT_EQ(Call("DELETE", path).first, 404);  // twice: unknown now, nothing else goes
  const json after = state();
  EXPECT_EQ(after["events"].size() + 1, before["events"].size());
  for (const json& e : after["events"]) EXPECT_NE(e["id"], id);
  for (const json& k : wrong["evidence"]) Ok("GET", "/v1/maps/home/keyframes/" + std::to_string(k["keyframe"].get<std::int64_t>()));
  bool kept_position = false;
  for (std::size_t i = 0; i < after["instances"].size(); ++i) {
    const json& h = after["instances"][i]["history"];
    ASSERT_EQ(h.size(), before["instances"][i]["history"].size());
    for (std::size_t k = 0; k < h.size(); ++k) {
      EXPECT_NE(h[k]["event"], id);
      if (before["instances"][i]["history"][k]["event"] == id) kept_position = h[k]["event"].is_null();
    }
  }
  ASSERT_TRUE(wrong["instance"].is_number()) << wrong.dump();
  EXPECT_TRUE(kept_position) << before.dump();
  // Later automatic processing: the same keyframe re-analysed again does not bring the deleted event back.
  const json again = Ok("POST", "/v1/maps/home/keyframes/" + std::to_string(keyframe) + ":reanalyse");
  for (const json& e : again["events"]) EXPECT_FALSE(e["type"] == wrong["type"] && e["instance"] == wrong["instance"]) << e.dump();

  // The audit trail: the deletion with the event before and nothing after, by the admin; the attempts on unknown
  // events with their 404 (the reader's was refused before any handler ran: no entry).
  const json entries = Ok("GET", "/v1/audit?map=home&action=event.delete&limit=100")["entries"];
  int deletions = 0, unknown = 0;
  for (const json& e : entries) {
    EXPECT_EQ(e["actor"]["role"], "admin") << e.dump();
    if (e["resource"] == "event=" + std::to_string(id) && e["status"] == 200) {
      ++deletions;
      EXPECT_EQ(e["before"], wrong);
      EXPECT_TRUE(e["after"].is_null()) << e.dump();
    }
    if (e["resource"] == "event=999999") unknown += e["status"] == 404 && e["before"].is_null();
  }
  EXPECT_EQ(deletions, 1) << entries.dump(1);
  EXPECT_EQ(unknown, 1) << entries.dump(1);
}

TEST_F(EventsHttpTest, BadInputIsRefusedWithClearErrorsAndChangesNothing) {
  Ok("POST", "/v1/maps", R"({"id":"home","name":"flat"})", 201);
  const json table = Ok("POST", "/v1/maps/home/instances", R"({"kind":"object","label":"cup","position":[1,2,0.8]})", 201);
  const std::string id = std::to_string(table["id"].get<std::int64_t>());
  const auto snapshot = [&] { return Ok("GET", "/v1/maps/home/events").dump() + Ok("GET", "/v1/maps/home/instances").dump(); };
  const std::string before = snapshot();
  const struct {
    std::string method, path, body;
    int status;
    std::string field;
  } cases[] = {
      {"POST", "/v1/maps/home/events/999:label", R"({"label":"keys"})", 404, "event"},
      {"POST", "/v1/maps/home/events/abc:label", R"({"label":"keys"})", 404, "event"},
      {"POST", "/v1/maps/home/instances/" + id + ":label", R"({"label":""})", 422, "label"},
      {"POST", "/v1/maps/home/instances/" + id + ":label", R"({"label":"   "})", 422, "label"},
      {"POST", "/v1/maps/home/instances/" + id + ":label", R"({"label":7})", 400, "label"},
      {"POST", "/v1/maps/home/instances/" + id + ":label", R"({"label":"keys","source":"robot"})", 400, "source"},
      {"POST", "/v1/maps/home/instances/" + id + ":label", R"({"label":"keys","colour":"red"})", 400, ""},
      {"POST", "/v1/maps/home/instances/" + id + ":label", R"({"label":"keys")", 400, ""},
      {"POST", "/v1/maps/home/instances/424242:label", R"({"label":"keys"})", 404, "instance"},
      {"GET", "/v1/maps/home/where?label=cup&at=9000000000000000000", "", 422, "at"},
      {"GET", "/v1/maps/home/where?label=cup&at=2200-01-01T00:00:00Z", "", 422, "at"},
      {"GET", "/v1/maps/home/where?label=cup&at=2999-01-01T00:00:00Z", "", 400, "at"},
      {"GET", "/v1/maps/home/where?label=cup&at=yesterday", "", 400, "at"},
      {"GET", "/v1/maps/home/where", "", 400, "label"},
      {"GET", "/v1/maps/home/where?label=", "", 422, "label"},
      {"GET", "/v1/maps/home/where?label=unicorn", "", 404, "label"},
      {"GET", "/v1/maps/nowhere/where?label=cup", "", 404, "map"},
      {"GET", "/v1/maps/home/events?type=exploded", "", 400, "type"},
      {"GET", "/v1/maps/home/events?limit=0", "", 422, "limit"},
      {"GET", "/v1/maps/home/events?since=soon", "", 400, "since"},
      {"GET", "/v1/maps/home/instances?status=lost", "", 400, "status"},
      {"POST", "/v1/maps/home/instances", R"({"label":"table","position":[1,2]})", 400, "position"},
      {"POST", "/v1/maps/home/instances", R"({"label":"table","position":[1,2,3],"extent":[-1,1,1]})", 422, "extent"},
      {"POST", "/v1/maps/home/keyframes/5:reanalyse", "{}", 404, "keyframe"},
      {"POST", "/v1/maps/home/keyframes/5:score", R"({"relevance":2})", 422, "relevance"},
  };
  for (const auto& c : cases) {
    auto [status, body] = Call(c.method, c.path, c.body);
    EXPECT_EQ(status, c.status) << c.method << " " << c.path << " " << c.body << " -> " << body.dump();
    ASSERT_TRUE(body.contains("error")) << c.path;
    EXPECT_FALSE(body["error"].value("message", "").empty());
    if (!c.field.empty()) {
      EXPECT_EQ(body["error"].value("field", ""), c.field) << c.path << " " << body.dump();
    }
  }
  EXPECT_EQ(snapshot(), before);
  // A valid relabel works afterwards (the instance was entered by hand, so its label is an operator's).
  EXPECT_EQ(Call("POST", "/v1/maps/home/instances/" + id + ":label", R"({"label":"Coffee Cup"})").first, 409);
  Ok("POST", "/v1/maps/home/instances/" + id + ":label", R"({"label":"Coffee Cup","source":"operator"})");
  EXPECT_EQ(Ok("GET", "/v1/maps/home/where?label=coffee%20cup")["instance"], table["id"]);
}

}  // namespace
}  // namespace anchordb
