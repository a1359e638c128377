#include "tests/eval/month_eval.h"

#include <Eigen/Geometry>
#include <httplib.h>
#include <sqlite3.h>

#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <thread>

#include "sim/apartment.h"
#include "sim/scenario_driver.h"
#include "storage/forgetting.h"

namespace anchordb::testing {
namespace {

using nlohmann::json;
using sim::Rng;

constexpr int kKeys = 301;
constexpr std::int64_t kHourNs = 3'600'000'000'000LL;
constexpr std::int64_t kDayNs = 24 * kHourNs;

std::int64_t Count(const std::string& db, const std::string& sql) {
  sqlite3* h = nullptr;
  sqlite3_open_v2(db.c_str(), &h, SQLITE_OPEN_READONLY, nullptr);
  sqlite3_stmt* s = nullptr;
  std::int64_t n = -1;
  if (sqlite3_prepare_v2(h, sql.c_str(), -1, &s, nullptr) == SQLITE_OK && sqlite3_step(s) == SQLITE_ROW) n = sqlite3_column_int64(s, 0);
  sqlite3_finalize(s);
  sqlite3_close(h);
  return n;
}

// A pose within a few cm and degrees of X (inside the supersession thresholds of 15 cm and 10 deg).
Eigen::Isometry3d Jitter(const Eigen::Isometry3d& X, Rng& rng) {
  const Eigen::Vector3d axis = Eigen::Vector3d(rng.Uniform(-1, 1), rng.Uniform(-1, 1), rng.Uniform(-1, 1)).normalized();
  const Eigen::Vector3d shift(rng.Uniform(-0.03, 0.03), rng.Uniform(-0.03, 0.03), rng.Uniform(-0.01, 0.01));
  return Eigen::Translation3d(shift) * X * Eigen::AngleAxisd(rng.Uniform(0.0, 0.035), axis);
}

}  // namespace

MonthResult RunMonth(const std::string& db_path, int port, int days, bool verbose) {
  httplib::Client client("127.0.0.1", port);
  client.set_read_timeout(120, 0);
  sim::ScenarioDriver d(client, "home", verbose ? std::function<void(const std::string&)>([](const std::string& l) { std::printf("    %s\n", l.c_str()); })
                                                 : std::function<void(const std::string&)>());
  d.Call("POST", "/v1/maps", {{"id", "home"}, {"name", "a month"}}, 201);
  Rng rng(2026);
  sim::SettingScene a = sim::MakeSetting(sim::Setting::kTA, 5);
  for (int id : a.movable_ids) sim::RemoveObject(a.scene, id);
  for (int id : {a.thin_object_id, a.tall_object_id}) sim::RemoveObject(a.scene, id);
  sim::SettingScene b = sim::MakeSetting(sim::Setting::kSE, 5);
  for (int id : b.movable_ids) sim::RemoveObject(b.scene, id);
  const Eigen::Isometry3d X_Map_B(Eigen::Translation3d(0.0, 10.0, 0.0));
  const auto [table_lo, table_hi] = sim::Bounds(a.scene, 10);
  const auto [shelf_lo, shelf_hi] = sim::Bounds(b.scene, 10);
  const Eigen::Vector3d table_c = 0.5 * (table_lo + table_hi), shelf_c = X_Map_B * (0.5 * (shelf_lo + shelf_hi));
  d.Call("POST", "/v1/maps/home/instances", {{"kind", "furniture"}, {"label", "table"}, {"position", {table_c.x(), table_c.y(), table_c.z()}},
                                              {"extent", {(table_hi - table_lo).x(), (table_hi - table_lo).y(), (table_hi - table_lo).z()}}}, 201);
  d.Call("POST", "/v1/maps/home/instances", {{"kind", "furniture"}, {"label", "shelf"}, {"position", {shelf_c.x(), shelf_c.y(), shelf_c.z()}},
                                              {"extent", {(shelf_hi - shelf_lo).x(), (shelf_hi - shelf_lo).y(), (shelf_hi - shelf_lo).z()}}}, 201);
  const Eigen::Vector3d keys_size(0.12, 0.08, 0.06);
  const Eigen::Vector3d keys_at_a = a.surface_point_m + Eigen::Vector3d(-0.1, -0.2, 0.03);
  const Eigen::Vector3d keys_at_b = b.surface_point_m + Eigen::Vector3d(0.0, 0.0, 0.03);
  const std::int64_t t0 = 1'767'225'600'000'000'000LL;  // 2026-01-01T00:00Z
  const int frames = 10;
  char keys_place = 0;  // 0: nowhere yet, 'A' or 'B'
  MonthResult result;
  std::uint64_t seed = 1;
  // One visit: `before`/`after` say where the keys are at the start and end of the observation.
  const auto visit = [&](char place, const Eigen::Isometry3d& X_view, bool keys_before, bool keys_after, std::int64_t start_ns,
                         const std::string& what) {
    const bool at_b = place == 'B';
    const Eigen::Isometry3d X_true = Jitter(X_view, rng);
    const sim::Scene& base = at_b ? b.scene : a.scene;
    const Eigen::Vector3d keys_local = at_b ? keys_at_b : keys_at_a;
    const sim::Primitive person = sim::PersonBeside(at_b ? b.surface_point_m : a.surface_point_m, X_true);
    d.Observe(what, X_true, at_b ? X_Map_B * X_true : X_true, frames, [&](int i) {
      sim::Scene s = base;
      if (i < 4 ? keys_before : keys_after) sim::AddBox(s, kKeys, "keys", keys_local + Eigen::Vector3d(0, 0, 0.5 * keys_size.z() - 0.03), keys_size, 0.3);
      const bool with_person = keys_before != keys_after && i >= 3 && i < 6;
      if (with_person) s.objects.push_back({sim::kPersonId, "person", "person"}), s.primitives.push_back(person);
      return std::make_pair(s, with_person);
    }, start_ns, ++seed);
  };
  for (int day = 0; day < days; ++day) {
    const std::int64_t morning = t0 + day * kDayNs + 9 * kHourNs;
    // Whether the keys are at the visited place at the start and at the end of each of the day's three visits.
    // Day 0: brought to the table (and named). Every third day they go to the shelf, the day after they come back.
    const char k = keys_place;
    bool plan[3][2] = {{k == 'A', k == 'A'}, {k == 'B', k == 'B'}, {k == 'A', k == 'A'}};
    char after = k;
    if (day == 0) plan[0][1] = plan[2][0] = plan[2][1] = true, after = 'A';
    else if (day % 3 == 1 && k == 'A') plan[0][1] = false, plan[1][1] = true, plan[2][0] = plan[2][1] = false, after = 'B';
    else if (day % 3 == 2 && k == 'B') plan[1][1] = false, plan[2][1] = true, after = 'A';
    const std::string name = "day " + std::to_string(day);
    visit('A', a.X_WorldCameraA, plan[0][0], plan[0][1], morning, name + " morning, table");
    if (day == 0) {
      const json added = d.Call("GET", "/v1/maps/home/events?type=added", json(), 200)["events"];
      if (!added.empty()) d.Call("POST", "/v1/maps/home/events/" + std::to_string(added.back()["id"].get<std::int64_t>()) + ":label", {{"label", "keys"}}, 200);
    }
    visit('B', b.X_WorldCameraA, plan[1][0], plan[1][1], morning + 4 * kHourNs, name + " noon, shelf");
    visit('A', a.X_WorldCameraB, plan[2][0], plan[2][1], morning + 9 * kHourNs, name + " evening, table from the side");
    keys_place = after;
    // The night: forgetting by the simulated clock, then the measurements.
    const std::int64_t night = t0 + day * kDayNs + 23 * kHourNs;
    const json policy = {{"keyframe_max_age_s", 3 * 86400}, {"event_max_age_s", 7 * 86400}, {"vacuum", true}};
    const json job = d.Call("POST", "/v1/maps/home:forget", {{"policy", policy}, {"now", night}}, 202);
    json state;
    for (int poll = 0; poll < 600; ++poll) {
      state = d.Call("GET", "/v1/jobs/" + std::to_string(job["job"].get<std::int64_t>()), json(), 200);
      if (state["status"] == "succeeded" || state["status"] == "failed") break;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    if (state["status"] != "succeeded") throw std::runtime_error("forgetting job: " + state.dump());
    MonthDay m;
    m.day = day + 1;
    m.file_bytes = storage::DatabaseFileBytes(db_path);
    m.keyframes = Count(db_path, "SELECT COUNT(*) FROM keyframes");
    m.models_with_state = Count(db_path, "SELECT COUNT(*) FROM scene_models WHERE background IS NOT NULL");
    m.events = Count(db_path, "SELECT COUNT(*) FROM events");
    m.forgotten_keyframes = static_cast<std::int64_t>(state["result"].value("keyframes_deleted", json::array()).size());
    auto where = client.Get("/v1/maps/home/where?label=keys");
    if (where && where->status == 200) {
      const json w = json::parse(where->body);
      const std::string sentence = w.value("sentence", "");
      m.where_right = w.value("present", false) && sentence.find(keys_place == 'A' ? "table" : "shelf") != std::string::npos;
    }
    result.days.push_back(m);
    if (verbose) {
      std::printf("day %2d  %8.2f MB  keyframes %4lld  models with state %3lld  events %4lld  forgotten keyframes %3lld  where %s\n",
                  m.day, m.file_bytes / 1e6, static_cast<long long>(m.keyframes), static_cast<long long>(m.models_with_state),
                  static_cast<long long>(m.events), static_cast<long long>(m.forgotten_keyframes), m.where_right ? "right" : "WRONG");
    }
  }
  // Every remaining event resolves its evidence.
  const json events = d.Call("GET", "/v1/maps/home/events?limit=1000", json(), 200)["events"];
  for (const json& e : events) {
    ++result.events_checked;
    for (const json& k : e["evidence"]) {
      auto r = client.Get("/v1/maps/home/keyframes/" + std::to_string(k["keyframe"].get<std::int64_t>()));
      if (!r || r->status != 200) ++result.evidence_missing;
    }
  }
  // A dry run changes nothing.
  const std::int64_t before = Count(db_path, "SELECT (SELECT COUNT(*) FROM keyframes) * 1000000 + (SELECT COUNT(*) FROM events) * 1000 + "
                                             "(SELECT COUNT(*) FROM scene_models WHERE background IS NOT NULL)");
  const json dry = d.Call("POST", "/v1/maps/home:forget", {{"policy", {{"keyframe_max_age_s", 0}, {"event_max_age_s", 0}}}, {"dry_run", true}}, 202);
  for (int poll = 0; poll < 600; ++poll) {
    const json s = d.Call("GET", "/v1/jobs/" + std::to_string(dry["job"].get<std::int64_t>()), json(), 200);
    if (s["status"] == "succeeded" || s["status"] == "failed") break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  const std::int64_t after = Count(db_path, "SELECT (SELECT COUNT(*) FROM keyframes) * 1000000 + (SELECT COUNT(*) FROM events) * 1000 + "
                                            "(SELECT COUNT(*) FROM scene_models WHERE background IS NOT NULL)");
  result.dry_run_changes = after - before;
  return result;
}

}  // namespace anchordb::testing
