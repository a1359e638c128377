// Trained E-SAMME classifiers over real HTTP on loopback: training as a job with a cross-validation report,
// predictions identical after a restart, bad input refused with nothing stored, cancellation of a running job.
#include "api/http_api.h"  // Eigen before httplib (see api/http_api.h)
#include "tests/support/grid_test_map.h"
#include "tests/support/server_process.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>
#include <httplib.h>

#include <chrono>
#include <random>
#include <thread>

#include <nlohmann/json.hpp>

namespace anchordb {
namespace classifiers_http_test {

using nlohmann::json;

// Three classes of 2-D Gaussians 4 apart ("signal") and a pure-noise type ("noise").
json Samples(int per_class, std::uint64_t seed, bool labelled = true) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  const char* names[] = {"kitchen", "bathroom", "office"};
  json samples = json::array();
  for (int c = 0; c < 3; ++c) {
    for (int i = 0; i < per_class; ++i) {
      json s = {{"features", {{"signal", {4.0 * c + n(rng), -4.0 * c + n(rng)}}, {"noise", {n(rng), n(rng), n(rng)}}}}};
      if (labelled) s["label"] = names[c];
      samples.push_back(s);
    }
  }
  return samples;
}

class ClassifiersHttpTest : public ::testing::Test {
 protected:
  void Start() {
    server_ = std::make_unique<testing::ServerProcess>(dir_.File("db.sqlite"));
    client_ = std::make_unique<httplib::Client>("127.0.0.1", server_->port());
    client_->set_read_timeout(60, 0);
  }
  void Restart() {
    client_.reset();
    ASSERT_EQ(server_->Stop(), 0);
    server_.reset();
    Start();
  }
  json Call(const std::string& method, const std::string& path, const json& body, int expected) {
    auto r = method == "GET" ? client_->Get(path) : client_->Post(path, body.dump(), "application/json");
    EXPECT_TRUE(r) << path;
    if (!r) return {};
    EXPECT_EQ(r->status, expected) << path << " " << r->body;
    return json::parse(r->body, nullptr, false);
  }
  json WaitJob(std::int64_t id) {
    for (int i = 0; i < 1200; ++i) {
      json j = Call("GET", "/v1/jobs/" + std::to_string(id), {}, 200);
      if (j.value("status", "") == "succeeded" || j.value("status", "") == "failed") return j;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return {};
  }
  json Training(const std::string& name) {
    return {{"name", name}, {"samples", Samples(20, 1)}, {"rounds", 10}, {"folds", 4}, {"seed", 3},
            {"base", {{{"kind", "dtree"}, {"max_depth", 1}}, {{"kind", "dtree"}, {"max_depth", 3}}, {{"kind", "knn"}, {"k", 3}},
                      {{"kind", "svm"}, {"C", {1, 10}}, {"gamma", 0.5}}}}};
  }

  testing::TempDir dir_;
  std::unique_ptr<testing::ServerProcess> server_;
  std::unique_ptr<httplib::Client> client_;
};

TEST_F(ClassifiersHttpTest, TrainReportPredictAndRestart) {
  Start();
  const json ticket = Call("POST", "/v1/classifiers", Training("rooms"), 202);
  const json done = WaitJob(ticket["job"].get<std::int64_t>());
  ASSERT_EQ(done.value("status", ""), "succeeded") << done.dump();
  const json model = Call("GET", "/v1/classifiers/rooms", {}, 200);
  EXPECT_EQ(model["classes"], json({"kitchen", "bathroom", "office"}));
  const json& cv = model["report"]["cross_validation"];
  EXPECT_EQ(cv["folds"], 4);
  EXPECT_LE(cv["test_error"].get<double>(), 0.1);
  EXPECT_EQ(cv["test_error_per_round"].size(), 10u);
  EXPECT_EQ(cv["confusion"].size(), 3u);
  EXPECT_LT(cv["feature_share"].value("noise", 0.0), 0.2);
  EXPECT_EQ(model["report"]["rounds"].size(), static_cast<std::size_t>(model["rounds"].get<int>()));
  EXPECT_EQ(Call("GET", "/v1/classifiers", {}, 200)["classifiers"].size(), 1u);
  // The stored options (typed documents, issue 30) as the request gave them, each base setting with its kind's
  // parameters only; the job's request says what the samples were, its result what came of them.
  const json& options = model["options"];
  EXPECT_EQ(options["name"], "rooms");
  EXPECT_EQ(options["rounds"], 10);
  EXPECT_EQ(options["folds"], 4);
  EXPECT_EQ(options["seed"], 3);
  ASSERT_GE(options["base"].size(), 4u) << options.dump();  // the SVM's C list is a grid of settings
  EXPECT_EQ(options["base"][1], json({{"kind", "dtree"}, {"max_depth", 3}, {"min_samples", 2}}));
  EXPECT_EQ(options["base"][2], json({{"kind", "knn"}, {"k", 3}}));
  EXPECT_EQ(options["base"][3]["kind"], "svm");
  EXPECT_EQ(options["base"][3]["gamma"], 0.5);
  EXPECT_EQ(done["request"]["sample_count"], 60);
  EXPECT_EQ(done["request"]["class_counts"], json({{"bathroom", 20}, {"kitchen", 20}, {"office", 20}}));
  EXPECT_EQ(done["request"]["base"], options["base"]);
  EXPECT_EQ(done["result"]["name"], "rooms");
  EXPECT_EQ(done["result"]["rounds"], model["rounds"]);
  EXPECT_EQ(done["result"]["test_error"], cv["test_error"]);

  const json probe = {{"samples", Samples(5, 99, false)}};
  const json before = Call("POST", "/v1/classifiers/rooms:predict", probe, 200);
  ASSERT_EQ(before["predictions"].size(), 15u);
  int right = 0;
  for (int i = 0; i < 15; ++i) right += before["predictions"][i]["label"] == json({"kitchen", "bathroom", "office"})[i / 5];
  EXPECT_GE(right, 13);
  Restart();
  EXPECT_EQ(Call("POST", "/v1/classifiers/rooms:predict", probe, 200), before);  // the reloaded model, bit for bit

  // Bad input: refused, nothing stored or queued.
  const auto refused = [&](json body, int status, const std::string& field) {
    const json e = Call("POST", "/v1/classifiers", body, status);
    EXPECT_EQ(e["error"]["field"], field) << body.dump();
  };
  json one_class = Training("bad");
  for (json& s : one_class["samples"]) s["label"] = "kitchen";
  refused(one_class, 422, "samples");
  json lonely = Training("bad");
  lonely["samples"][0]["label"] = "attic";  // a class with one sample
  refused(lonely, 422, "samples");
  json short_descriptor = Training("bad");
  short_descriptor["samples"][3]["features"]["signal"] = {1.0};
  refused(short_descriptor, 400, "samples[3].features.signal");
  json folds = Training("bad");
  folds["folds"] = 61;
  refused(folds, 422, "folds");
  json rounds = Training("bad");
  rounds["rounds"] = 100000;
  refused(rounds, 400, "rounds");
  json shrink = Training("bad");
  shrink["learning_rate"] = 0;
  refused(shrink, 400, "learning_rate");
  json measure = Training("bad");
  measure["error_on"] = "test_set";
  refused(measure, 400, "error_on");
  json kind = Training("bad");
  kind["base"] = {{{"kind", "forest"}}};
  refused(kind, 400, "kind");
  json empty = Training("bad");
  empty["samples"] = json::array();
  refused(empty, 400, "samples");
  auto nan = client_->Post("/v1/classifiers", R"({"name":"bad","samples":[{"label":"a","features":{"x":[NaN]}}]})", "application/json");
  ASSERT_TRUE(nan);
  EXPECT_EQ(nan->status, 400);
  EXPECT_EQ(Call("GET", "/v1/classifiers", {}, 200)["classifiers"].size(), 1u);
  Call("GET", "/v1/classifiers/bad", {}, 404);
  Call("POST", "/v1/classifiers/rooms:predict", {{"samples", {{{"features", {{"signal", {1, 2}}}}}}}}, 400);  // no noise type
  // A type the classifier was not trained on (here a misspelt one beside the right two) is refused, not ignored.
  json misspelt = probe;
  misspelt["samples"][2]["features"]["nosie"] = {0.0, 0.0, 0.0};
  const json unknown_type = Call("POST", "/v1/classifiers/rooms:predict", misspelt, 400);
  EXPECT_EQ(unknown_type["error"]["field"], "samples[2].features.nosie") << unknown_type.dump();
  EXPECT_EQ(Call("GET", "/v1/classifiers", {}, 200)["classifiers"].size(), 1u);
  EXPECT_EQ(Call("POST", "/v1/classifiers/rooms:predict", probe, 200), before);  // the model is unchanged
  Call("POST", "/v1/classifiers/nothing:predict", probe, 404);
}

// The training job's document (the 202 ticket, GET /v1/jobs/{id}, the job list) keeps the options and says how many
// samples of which class and feature type there were; it does not echo the samples.
TEST_F(ClassifiersHttpTest, TrainingJobDocumentHoldsCountsNotSamples) {
  Start();
  const json body = Training("rooms");
  const json ticket = Call("POST", "/v1/classifiers", body, 202);
  const std::int64_t id = ticket["job"].get<std::int64_t>();
  const json done = WaitJob(id);
  ASSERT_EQ(done.value("status", ""), "succeeded") << done.dump();
  const json jobs = Call("GET", "/v1/jobs", {}, 200);
  json listed;
  for (const json& j : jobs["jobs"]) if (j["id"] == id) listed = j;
  ASSERT_TRUE(listed.is_object()) << jobs.dump().substr(0, 400);
  for (const json& request : {ticket["request"], done["request"], listed["request"]}) {
    ASSERT_TRUE(request.is_object()) << request.dump();
    EXPECT_FALSE(request.contains("samples")) << request.dump().substr(0, 300);
    EXPECT_EQ(request["name"], "rooms");
    EXPECT_EQ(request["rounds"], 10);
    EXPECT_EQ(request["folds"], 4);
    EXPECT_EQ(request["seed"], 3);
    EXPECT_EQ(request["base"].size(), 5u);  // the SVM's C grid {1, 10} is two settings
    EXPECT_EQ(request["sample_count"], 60);
    EXPECT_EQ(request["class_counts"], json({{"kitchen", 20}, {"bathroom", 20}, {"office", 20}}));
    EXPECT_EQ(request["feature_dims"], json({{"signal", 2}, {"noise", 3}}));
    EXPECT_LT(request.dump().size(), body.dump().size() / 4);
  }
  // A second training (the staged samples of the first are gone) still runs, and the model predicts.
  const json again = Call("POST", "/v1/classifiers", Training("rooms2"), 202);
  ASSERT_EQ(WaitJob(again["job"].get<std::int64_t>()).value("status", ""), "succeeded");
  EXPECT_EQ(Call("POST", "/v1/classifiers/rooms2:predict", {{"samples", Samples(1, 7, false)}}, 200)["predictions"].size(), 3u);
}

TEST_F(ClassifiersHttpTest, TrainingCanBeCancelled) {
  Start();
  json slow = Training("slow");
  slow["samples"] = Samples(150, 5);
  slow["rounds"] = 300;
  slow["base"] = {{{"kind", "mlp"}, {"hidden", {64}}, {"iterations", 300}}, {{"kind", "svm"}, {"C", {1, 10, 100}}, {"gamma", {0.1, 1}}}};
  const json ticket = Call("POST", "/v1/classifiers", slow, 202);
  const std::string job = std::to_string(ticket["job"].get<std::int64_t>());
  EXPECT_EQ(Call("POST", "/v1/jobs/" + job + ":cancel", json::object(), 200)["cancelled"], true);
  const json done = WaitJob(ticket["job"].get<std::int64_t>());
  EXPECT_EQ(done.value("status", ""), "failed");
  EXPECT_EQ(done.value("error", ""), "cancelled");
  Call("GET", "/v1/classifiers/slow", {}, 404);
}

// Two rooms side by side in a map, each with features of its own kind; a classifier trained on bags of words of the
// map's codebook names each region and paints it into a label layer.
TEST_F(ClassifiersHttpTest, RoomsAreClassifiedFromTheirBagsOfWords) {
  Start();
  Call("POST", "/v1/maps", {{"id", "home"}, {"name", "home"}}, 201);
  auto occ = client_->Put("/v1/maps/home/layers/occ",
                          httplib::MultipartFormDataItems{{"yaml", testing::GridTestYaml(), "map.yaml", "text/yaml"},
                                                          {"image", testing::GridTestPgm(), "map.pgm", "image/x-portable-graymap"}});
  ASSERT_TRUE(occ && occ->status / 100 == 2) << (occ ? occ->body : "");
  auto rooms = client_->Put("/v1/maps/home/layers/rooms", R"({"kind":"label","base":"occ"})", "application/json");
  ASSERT_TRUE(rooms && rooms->status / 100 == 2) << (rooms ? rooms->body : "");
  // Room A (x < 1): mostly descriptors near 0; room B (x > 1): mostly near 10.
  json features = json::array();
  for (int i = 0; i < 12; ++i) {
    const double v = i < 9 ? 0.1 * i : 10.0;
    features.push_back({{"descriptor", {v, 0.0}}, {"anchor_m", {0.2 + 0.05 * i, 0.5, 0.3}}});
    features.push_back({{"descriptor", {10.0 - (i < 9 ? 0.1 * i : 10.0), 0.0}}, {"anchor_m", {1.6 + 0.05 * i, 0.5, 0.3}}});
  }
  Call("POST", "/v1/maps/home/features", {{"type", "x_look"}, {"features", features}}, 200);
  const json job = Call("POST", "/v1/maps/home/codebooks", {{"type", "x_look"}, {"words", 2}, {"seed", 1}}, 202);
  ASSERT_EQ(WaitJob(job["job"].get<std::int64_t>()).value("status", ""), "succeeded");
  const json centres = Call("GET", "/v1/maps/home/codebooks/x_look?centres=true", {}, 200)["centres"];
  const int low = centres[0].get<double>() < centres[2].get<double>() ? 0 : 1;  // the word of the descriptors near 0
  // Kitchens are mostly low words, bathrooms mostly high ones.
  json samples = json::array();
  for (int i = 0; i < 6; ++i) {
    std::vector<double> kitchen(2), bathroom(2);
    kitchen[low] = 0.7 + 0.04 * i;
    kitchen[1 - low] = 1 - kitchen[low];
    bathroom[1 - low] = 0.7 + 0.04 * i;
    bathroom[low] = 1 - bathroom[1 - low];
    samples.push_back({{"label", "kitchen"}, {"features", {{"x_look", kitchen}}}});
    samples.push_back({{"label", "bathroom"}, {"features", {{"x_look", bathroom}}}});
  }
  const json trained = Call("POST", "/v1/classifiers", {{"name", "rooms"}, {"samples", samples}, {"rounds", 5}, {"folds", 3},
                                                        {"base", {{{"kind", "dtree"}, {"max_depth", 1}}}}}, 202);
  ASSERT_EQ(WaitJob(trained["job"].get<std::int64_t>()).value("status", ""), "succeeded");
  const json regions = {{{"id", "A"}, {"polygon", {{-0.5, -0.5}, {0.95, -0.5}, {0.95, 1.5}, {-0.5, 1.5}}}},
                        {{"id", "B"}, {"polygon", {{1.05, -0.5}, {2.9, -0.5}, {2.9, 1.5}, {1.05, 1.5}}}}};
  const json result = Call("POST", "/v1/maps/home/rooms:classify", {{"classifier", "rooms"}, {"regions", regions}, {"into", "rooms"}}, 200);
  ASSERT_EQ(result["regions"].size(), 2u);
  EXPECT_EQ(result["regions"][0]["label"], "kitchen");
  EXPECT_EQ(result["regions"][1]["label"], "bathroom");
  EXPECT_EQ(result["regions"][0]["features"], json({12}));
  EXPECT_GT(result["regions"][0]["distribution"]["kitchen"].get<double>(), 0.5);
  auto layer = client_->Get("/v1/maps/home/layers/rooms");
  ASSERT_TRUE(layer && layer->status == 200);
  EXPECT_NE(layer->body.find("kitchen"), std::string::npos) << layer->body;
  EXPECT_NE(layer->body.find("bathroom"), std::string::npos) << layer->body;
  Call("POST", "/v1/maps/home/rooms:classify", {{"classifier", "nothing"}, {"regions", regions}}, 404);
  Call("POST", "/v1/maps/home/rooms:classify", {{"classifier", "rooms"}, {"regions", json::array()}}, 400);
  Call("POST", "/v1/maps/home/rooms:classify", {{"classifier", "rooms"}, {"regions", {{{"polygon", {{0, 0}, {1, 1}}}}}}}, 400);
}

}  // namespace
}  // namespace anchordb
