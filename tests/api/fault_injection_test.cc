// Fault injection over a representative request mix (SPEC §8, issue 12): the server as server/main.cc composes it
// (services::Capabilities + api::HttpApi on a real cpp-httplib server on loopback, in this process), its SQLite
// connections opened through the fault VFS (storage/fault_vfs.h). For each request of the mix and each fault kind,
// N = 1, 2, ... until the request succeeds: the Nth write / sync / allocation fails, or the disk fills after
// (N - 1) * 4 KiB. Each time: the answer is success or a clear JSON error (503 with Retry-After, 507), never another
// 5xx; reads keep answering while the fault is armed; after disarming, integrity_check is ok, foreign_key_check is
// empty, and the database holds either none of the request (an error: the logical snapshot equals the one before)
// or all of it (a success: the snapshot equals a fault-free run's after the same request). The frame count the
// server reports always equals the frames answered 200. Jobs (forgetting, backup) end succeeded or failed with
// their work committed whole or not at all.
#include "api/http_api.h"  // Eigen before httplib (see api/http_api.h)
#include "api/routes.h"
#include "engine/scene/depth_image.h"
#include "services/capabilities.h"
#include "storage/fault_vfs.h"
#include "storage/store.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>
#include <httplib.h>
#include <sqlite3.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <map>
#include <thread>

namespace anchordb {
namespace fault_injection_test {

namespace fault = storage::fault;
using nlohmann::json;

constexpr std::int64_t kNowNs = 1'800'000'000'000'000'000LL;
constexpr std::int64_t kSceneNs = kNowNs - 3'600'000'000'000LL;  // an hour ago: old enough to forget
constexpr std::int64_t kDiskStepBytes = 4096;
constexpr std::int64_t kMaxAttempts = 5000;

// The server of server/main.cc, in process: a store whose connections use the fault VFS, every capability on a
// standing clock (two runs write the same rows), every route on a loopback httplib server.
class InProcessServer {
 public:
  InProcessServer(const std::string& db, const std::string& backup_dir)
      : store_(StoreOptionsFor(db)), capabilities_(store_, CapabilitiesFor(backup_dir), clock_), api_(api::HttpOptions{}) {
    api::RegisterAllRoutes(api_.router(), capabilities_);
    api_.Mount(server_);
    port_ = server_.bind_to_any_port("127.0.0.1");
    serving_ = std::thread([this] { server_.listen_after_bind(); });
    client_ = std::make_unique<httplib::Client>("127.0.0.1", port_);
    client_->set_read_timeout(60, 0);
  }
  ~InProcessServer() {
    client_.reset();
    server_.stop();
    serving_.join();
  }
  httplib::Client& client() { return *client_; }
  services::Capabilities& capabilities() { return capabilities_; }

 private:
  static storage::StoreOptions StoreOptionsFor(const std::string& db) {
    storage::StoreOptions o;
    o.path = db;
    o.connection.vfs = fault::kFaultVfsName;
    return o;
  }
  static services::CapabilityOptions CapabilitiesFor(const std::string& backup_dir) {
    services::CapabilityOptions o;
    o.jobs.backup_dir = backup_dir;
    return o;
  }

  FakeClock clock_{kNowNs};
  storage::Store store_;
  services::Capabilities capabilities_;
  api::HttpApi api_;
  httplib::Server server_;
  int port_ = 0;
  std::thread serving_;
  std::unique_ptr<httplib::Client> client_;
};

// The database's logical content read past the fault VFS: per table, its rows as sorted text (blobs by size and
// hash). `skip` leaves tables out.
std::map<std::string, std::vector<std::string>> Snapshot(const std::string& db, const std::vector<std::string>& skip = {}) {
  sqlite3* c = nullptr;
  EXPECT_EQ(sqlite3_open_v2(db.c_str(), &c, SQLITE_OPEN_READONLY, "unix"), SQLITE_OK);
  std::map<std::string, std::vector<std::string>> out;
  std::vector<std::string> tables;
  sqlite3_stmt* s = nullptr;
  sqlite3_prepare_v2(c, "SELECT name FROM sqlite_schema WHERE type = 'table' AND name NOT LIKE 'sqlite_stat%' ORDER BY name",
                     -1, &s, nullptr);
  while (sqlite3_step(s) == SQLITE_ROW) tables.emplace_back(reinterpret_cast<const char*>(sqlite3_column_text(s, 0)));
  sqlite3_finalize(s);
  for (const std::string& t : tables) {
    if (std::find(skip.begin(), skip.end(), t) != skip.end()) continue;
    auto& rows = out[t];
    sqlite3_prepare_v2(c, ("SELECT * FROM \"" + t + "\"").c_str(), -1, &s, nullptr);
    while (sqlite3_step(s) == SQLITE_ROW) {
      std::string row;
      for (int i = 0; i < sqlite3_column_count(s); ++i) {
        if (sqlite3_column_type(s, i) == SQLITE_BLOB) {
          const std::string blob(static_cast<const char*>(sqlite3_column_blob(s, i)), sqlite3_column_bytes(s, i));
          row += "blob" + std::to_string(blob.size()) + ":" + std::to_string(std::hash<std::string>{}(blob));
        } else if (const auto* text = sqlite3_column_text(s, i)) {
          row += reinterpret_cast<const char*>(text);
        } else {
          row += "NULL";
        }
        row += "|";
      }
      // A skipped table's sequence goes with it.
      const std::string sequence_of = t == "sqlite_sequence" ? row.substr(0, row.find('|')) : "";
      if (std::find(skip.begin(), skip.end(), sequence_of) == skip.end()) rows.push_back(std::move(row));
    }
    sqlite3_finalize(s);
    std::sort(rows.begin(), rows.end());
  }
  sqlite3_close(c);
  return out;
}

using Tables = std::map<std::string, std::vector<std::string>>;

// The rows in which two snapshots differ ("-" only in `a`, "+" only in `b`), each cut to 160 characters; empty when
// they are equal.
std::string Diff(const Tables& a, const Tables& b) {
  std::string out;
  const auto cut = [](const std::string& row) { return row.substr(0, 160); };
  for (const auto& [table, rows] : a) {
    const auto& other = b.count(table) ? b.at(table) : std::vector<std::string>{};
    for (const auto& r : rows) if (std::find(other.begin(), other.end(), r) == other.end()) out += "\n- " + table + ": " + cut(r);
    for (const auto& r : other) if (std::find(rows.begin(), rows.end(), r) == rows.end()) out += "\n+ " + table + ": " + cut(r);
  }
  return out;
}

// The rows of `sql` (one statement) run past the fault VFS, values separated by spaces.
std::string Query(const std::string& db, const std::string& sql) {
  sqlite3* c = nullptr;
  sqlite3_open_v2(db.c_str(), &c, SQLITE_OPEN_READONLY, "unix");
  std::string out;
  sqlite3_stmt* s = nullptr;
  sqlite3_prepare_v2(c, sql.c_str(), -1, &s, nullptr);
  while (sqlite3_step(s) == SQLITE_ROW) {
    for (int i = 0; i < sqlite3_column_count(s); ++i) {
      const auto* text = sqlite3_column_text(s, i);
      out += (out.empty() ? "" : " ") + std::string(text ? reinterpret_cast<const char*>(text) : "NULL");
    }
  }
  sqlite3_finalize(s);
  sqlite3_close(c);
  return out;
}

// ---- the request mix ----

struct MixState {
  std::string scene;        // "/v1/maps/home/scenes/<id>"
  std::int64_t keyframe = 0;
  std::int64_t instance = 0;
  std::int64_t graph = 0;
  int frames_answered = 0;  // frames answered 200
};

struct Step {
  std::string name;
  std::function<httplib::Result(httplib::Client&, const MixState&)> send;
  std::function<void(const json&, MixState&)> taken;  // after a success: what the next steps refer to
  bool job = false;                                   // answered 202 with a job that runs after the answer
};

httplib::Result PostJson(httplib::Client& c, const std::string& path, const json& body) {
  return c.Post(path, body.dump(), "application/json");
}

std::string Pgm() {  // 40 x 30 cells, free with a wall
  std::string pixels(40 * 30, static_cast<char>(254));
  for (int y = 5; y < 25; ++y) pixels[y * 40 + 20] = 0;
  return "P5\n40 30\n255\n" + pixels;
}

std::string DepthPng(int frame) {
  std::vector<std::uint16_t> depth(64 * 48, 1500);
  for (int y = 10; y < 30; ++y) {
    for (int x = 20; x < 40; ++x) depth[y * 64 + x] = static_cast<std::uint16_t>(1200 + frame);  // a box
  }
  return engine::EncodeDepthPng(depth, 64, 48);
}

std::vector<Step> Mix() {
  const json square = json::array({json::array({0.9, 0.2}), json::array({1.2, 0.2}), json::array({1.2, 0.5}), json::array({0.9, 0.5})});
  const json pose = {{"position", {0.5, 0.5, 0.0}}, {"orientation", {0, 0, 0, 1}}};
  std::vector<Step> mix;
  auto add = [&](std::string name, auto send, std::function<void(const json&, MixState&)> taken = {}, bool job = false) {
    mix.push_back({std::move(name), send, std::move(taken), job});
  };
  add("create map", [](httplib::Client& c, const MixState&) { return PostJson(c, "/v1/maps", {{"id", "home"}, {"name", "Home"}}); });
  add("import layer", [](httplib::Client& c, const MixState&) {
    const std::string yaml = "image: map.pgm\nresolution: 0.1\norigin: [-1.0, -1.0, 0.0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
    httplib::MultipartFormDataItems items = {{"yaml", yaml, "map.yaml", "application/yaml"},
                                             {"image", Pgm(), "map.pgm", "image/x-portable-graymap"}};
    return c.Put("/v1/maps/home/layers/occ", items);
  });
  add("create probability layer", [](httplib::Client& c, const MixState&) {
    return c.Put("/v1/maps/home/layers/surface", json({{"kind", "probability"}, {"base", "occ"}}).dump(), "application/json");
  });
  add("grid observation", [=](httplib::Client& c, const MixState&) {
    return PostJson(c, "/v1/maps/home/layers/surface/observations",
                    {{"pose", pose}, {"fov_rad", 1.0}, {"range_m", 2.0}, {"stimulus", {square}}});
  });
  add("create label layer", [](httplib::Client& c, const MixState&) {
    return c.Put("/v1/maps/home/layers/rooms", json({{"kind", "label"}, {"base", "occ"}, {"labels", {{"1", "kitchen"}}}}).dump(),
                 "application/json");
  });
  add("paint label", [=](httplib::Client& c, const MixState&) {
    return PostJson(c, "/v1/maps/home/layers/rooms/labels", {{"label", "hall"}, {"polygons", {square}}});
  });
  add("open scene", [](httplib::Client& c, const MixState&) {
    const json camera = {{"width", 64}, {"height", 48}, {"fx", 60.0}, {"fy", 60.0}, {"cx", 31.5}, {"cy", 23.5}};
    return PostJson(c, "/v1/maps/home/scenes",
                    {{"camera", camera}, {"pose", {{"position", {0, 0, 1}}, {"orientation", {0, 0, 0, 1}}}}, {"stamp", kSceneNs}});
  }, [](const json& r, MixState& s) { s.scene = "/v1/maps/home/scenes/" + std::to_string(r.at("id").get<std::int64_t>()); });
  for (int i = 0; i < 3; ++i) {
    add("frame " + std::to_string(i + 1), [i](httplib::Client& c, const MixState& s) {
      return c.Post(s.scene + "/frames?stamp=" + std::to_string(kSceneNs + (i + 1) * 33'000'000LL), DepthPng(i), "image/png");
    }, [](const json&, MixState& s) { ++s.frames_answered; });
  }
  add("keyframe", [](httplib::Client& c, const MixState& s) { return c.Post(s.scene + "/keyframes", "", "application/json"); },
      [](const json& r, MixState& s) { s.keyframe = r.at("keyframe").get<std::int64_t>(); });
  add("close scene", [](httplib::Client& c, const MixState& s) { return c.Post(s.scene + ":close", "", "application/json"); });
  add("pin keyframe", [](httplib::Client& c, const MixState& s) {
    return c.Post("/v1/maps/home/keyframes/" + std::to_string(s.keyframe) + ":pin", "", "application/json");
  });
  add("create instance", [](httplib::Client& c, const MixState&) {
    return PostJson(c, "/v1/maps/home/instances", {{"kind", "object"}, {"label", "keys"}, {"position", {1.0, 0.5, 0.8}}});
  }, [](const json& r, MixState& s) { s.instance = r.at("id").get<std::int64_t>(); });
  add("label instance", [](httplib::Client& c, const MixState& s) {
    return PostJson(c, "/v1/maps/home/instances/" + std::to_string(s.instance) + ":label", {{"label", "house keys"}, {"source", "operator"}});
  });
  add("pin instance", [](httplib::Client& c, const MixState& s) {
    return c.Post("/v1/maps/home/instances/" + std::to_string(s.instance) + ":pin", "", "application/json");
  });
  add("furniture graph", [](httplib::Client& c, const MixState&) {
    return PostJson(c, "/v1/maps/home/furniture-graphs", json::parse(R"({
      "viewpoint": {"position": [0, 0], "heading_rad": 0},
      "furniture": [
        {"id": "sofa", "position": [4.0, 0.0], "extent": [0.9, 2.0], "categories": {"sofa": 0.6, "armchair": 0.3, "table": 0.1}},
        {"id": "plant", "position": [4.0, 1.7], "extent": [0.4, 0.4], "categories": {"plant": 0.7, "stool": 0.3}},
        {"id": "table", "position": [2.8, 0.0], "extent": [0.6, 1.0], "categories": {"table": 0.6, "stool": 0.2, "chair": 0.2}}
      ]})"));
  }, [](const json& r, MixState& s) { s.graph = r.at("id").get<std::int64_t>(); });
  add("furniture description", [](httplib::Client& c, const MixState& s) {
    return PostJson(c, "/v1/maps/home/furniture-graphs/" + std::to_string(s.graph) + "/descriptions",
                    {{"text", "the plant is left of the sofa"}});
  });
  add("forgetting job", [](httplib::Client& c, const MixState&) {
    return PostJson(c, "/v1/maps/home:forget", {{"policy", {{"keyframe_max_age_s", 1.0}, {"event_max_age_s", 1.0}}},
                                                {"dry_run", false}});
  }, {}, true);
  add("backup job", [](httplib::Client& c, const MixState&) { return PostJson(c, "/v1/backups", {{"label", "nightly"}}); }, {}, true);
  return mix;
}

// The tables a fault-free run need not share: the migration stamps (wall clock) and the job rows (a failed job is
// kept, and a backup's result names its file). Jobs are checked on their own.
// The audit trail is a log of attempts (a failed edit is recorded with its status), not part of a request's effect;
// it is checked on its own: no entry claims a success for a request answered with an error.
const std::vector<std::string> kRunSpecific = {"schema_migrations", "jobs", "audit_log"};
const std::vector<std::string> kLogs = {"jobs", "audit_log"};
constexpr const char* kAuditSuccesses = "SELECT count(*) FROM audit_log WHERE status BETWEEN 200 AND 299";

struct Outcome {
  bool success = false;
  std::string detail;
};

// Sends `step` and, for a job, waits for it; checks the answer is a success or a clear error.
Outcome Send(InProcessServer& server, const Step& step, MixState& state) {
  auto r = step.send(server.client(), state);
  if (!r) return {false, "FAILED: no answer (" + httplib::to_string(r.error()) + ")"};
  const json body = json::parse(r->body, nullptr, false);
  if (r->status >= 200 && r->status < 300) {
    if (step.taken) step.taken(body, state);
    if (!step.job) return {true, ""};
    EXPECT_TRUE(server.capabilities().jobs.WaitIdle(120.0));
    const std::string path = "/v1/jobs/" + std::to_string(body.at("job").get<std::int64_t>());
    auto job = server.client().Get(path);
    if (job && job->status == 503 && job->has_header("Retry-After")) job = server.client().Get(path);  // a failed allocation
    if (!job || job->status != 200) return {false, "FAILED: the job cannot be read: " + (job ? job->body : "no answer")};
    const json j = json::parse(job->body);
    if (j["status"] == "succeeded") return {true, ""};
    if (j["status"] == "failed" && j["error"].is_string() && !j["error"].get<std::string>().empty()) return {false, "job failed"};
    return {false, "FAILED: job ended " + job->body};
  }
  const bool retry_after = r->status == 503 && r->has_header("Retry-After");
  const std::string code = body.is_object() && body.contains("error") ? body["error"].value("code", "") : "";
  const bool clear = (retry_after && (code == "unavailable" || code == "overloaded")) || (r->status == 507 && code == "insufficient_storage");
  return {false, (clear ? "" : "FAILED: ") + std::to_string(r->status) + " " + r->body};
}

fault::FaultPlan PlanFor(fault::FaultKind kind, std::int64_t n) {
  fault::FaultPlan plan;
  plan.kind = kind;
  plan.nth = n;
  plan.budget_bytes = (n - 1) * kDiskStepBytes;
  return plan;
}

class FaultInjection : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    fault::InstallAllocationHook();  // before the VFS: SQLite re-registers its own default VFS when it restarts
    fault::RegisterFaultVfs(true);   // the default too: job and backup connections go through it
  }

  void RunMix(fault::FaultKind kind) {
    // A fault-free run: the database after each request.
    std::vector<std::map<std::string, std::vector<std::string>>> reference;
    {
      InProcessServer server(dir_.File("reference.sqlite"), dir_.File("reference-backups"));
      MixState state;
      for (const Step& step : Mix()) {
        const Outcome outcome = Send(server, step, state);
        ASSERT_TRUE(outcome.success) << step.name << ": " << outcome.detail;
        reference.push_back(Snapshot(dir_.File("reference.sqlite"), kRunSpecific));
      }
    }
    const std::string db = dir_.File("faulted.sqlite");
    const std::string backups = dir_.File("faulted-backups");
    InProcessServer server(db, backups);
    MixState state;
    const auto mix = Mix();
    int errors = 0, fired_successes = 0;
    for (std::size_t i = 0; i < mix.size(); ++i) {
      const Step& step = mix[i];
      SCOPED_TRACE(step.name);
      for (std::int64_t n = 1;; ++n) {
        ASSERT_LT(n, kMaxAttempts) << "the request never succeeded";
        const auto before = Snapshot(db, kLogs);
        const std::string audit_successes_before = Query(db, kAuditSuccesses);
        fault::Arm(PlanFor(kind, n));
        const Outcome outcome = Send(server, step, state);
        const bool fired = fault::Fired();
        // Reads keep answering while the fault is armed (an allocation fault may hit a read once: 503).
        const auto read = server.client().Get("/v1/maps/home");
        fault::Disarm();
        ASSERT_EQ(outcome.detail.rfind("FAILED", 0), std::string::npos) << "N=" << n << ": " << outcome.detail;
        ASSERT_TRUE(read) << "N=" << n << ": no answer to a read while the fault is armed";
        const bool read_ok = read->status == 200 || (i == 0 && read->status == 404) ||
                             (kind == fault::FaultKind::kAllocation && read->status == 503 && read->has_header("Retry-After"));
        EXPECT_TRUE(read_ok) << "N=" << n << ": read while armed answered " << read->status << " " << read->body;
        ASSERT_EQ(Query(db, "PRAGMA integrity_check"), "ok") << "N=" << n;
        ASSERT_EQ(Query(db, "PRAGMA foreign_key_check"), "") << "N=" << n;
        if (!state.scene.empty()) {
          const auto scene = server.client().Get(state.scene);
          ASSERT_TRUE(scene && scene->status == 200);
          EXPECT_EQ(json::parse(scene->body)["frames"], state.frames_answered) << "N=" << n << ": frames claimed";
        }
        if (!outcome.success) {
          ++errors;
          ASSERT_EQ(Diff(before, Snapshot(db, kLogs)), "") << "N=" << n << ": an error left a partial write (" << outcome.detail << ")";
          if (!step.job) {  // a job's submission was answered 202 (and audited so); the job itself failed
            ASSERT_EQ(Query(db, kAuditSuccesses), audit_successes_before) << "N=" << n << ": the audit trail claims a success";
          }
          continue;
        }
        ASSERT_EQ(Diff(reference[i], Snapshot(db, kRunSpecific)), "") << "N=" << n << ": the success differs from a fault-free run";
        if (fired) ++fired_successes;  // the fault hit something the request survived (a checkpoint, a read)
        break;
      }
    }
    // Jobs: each ended succeeded or failed, none left queued or running; a failed backup left no file.
    EXPECT_EQ(Query(db, "SELECT count(*) FROM jobs WHERE status NOT IN ('succeeded', 'failed')"), "0")
        << Query(db, "SELECT id, kind, status, error FROM jobs");
    EXPECT_EQ(Query(db, "SELECT count(*) FROM jobs WHERE status = 'succeeded'"), "2");
    std::size_t files = 0;
    for (const auto& f : std::filesystem::directory_iterator(backups)) {
      EXPECT_EQ(f.path().extension(), ".sqlite") << f.path();
      ++files;
    }
    EXPECT_EQ(files, 1u);
    std::printf("fault %s: %d error answers, %d successes with the fault fired, over %zu requests\n",
                fault::FaultKindName(kind), errors, fired_successes, mix.size());
  }

  testing::TempDir dir_;
};

TEST_F(FaultInjection, NthWriteFailsOverTheRequestMix) { RunMix(fault::FaultKind::kWrite); }
TEST_F(FaultInjection, NthSyncFailsOverTheRequestMix) { RunMix(fault::FaultKind::kSync); }
TEST_F(FaultInjection, DiskFullOverTheRequestMix) { RunMix(fault::FaultKind::kDiskFull); }
TEST_F(FaultInjection, NthAllocationFailsOverTheRequestMix) { RunMix(fault::FaultKind::kAllocation); }

}  // namespace
}  // namespace anchordb
