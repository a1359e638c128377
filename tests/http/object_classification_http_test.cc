// Object classification over real HTTP on loopback (issue 15 "Object classification"): an object the robot saw appear
// (a change event with its segment) is classified by a trained E-SAMME classifier from the fpfh features of its
// segment and the map's codebook; the distribution becomes its label with source "classifier" and where-is finds it
// by that label; an operator's label is never overridden; bad requests are refused and store nothing.
#include "api/http_api.h"  // Eigen before httplib (see api/http_api.h)
#include "sim/apartment.h"
#include "sim/renderer.h"
#include "tests/support/server_process.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>
#include <httplib.h>

#include <chrono>
#include <cstdio>
#include <random>
#include <thread>

#include <nlohmann/json.hpp>

namespace anchordb {
namespace object_classification_http_test {

using nlohmann::json;

class ObjectClassificationHttpTest : public ::testing::Test {
 protected:
  void SetUp() override {
    server_ = std::make_unique<testing::ServerProcess>(dir_.File("objects.sqlite"));
    client_ = std::make_unique<httplib::Client>("127.0.0.1", server_->port());
    client_->set_read_timeout(120, 0);
  }
  json Raw(const std::string& method, const std::string& path, const std::string& body, int expected) {
    auto r = method == "GET" ? client_->Get(path) : client_->Post(path, body, "application/json");
    EXPECT_TRUE(r) << method << " " << path;
    if (!r) return {};
    EXPECT_EQ(r->status, expected) << method << " " << path << " " << r->body.substr(0, 600);
    return json::parse(r->body, nullptr, false);
  }
  json Call(const std::string& method, const std::string& path, const json& body, int expected) {
    return Raw(method, path, body.dump(), expected);
  }
  json WaitJob(const json& ticket) {
    const std::string path = "/v1/jobs/" + std::to_string(ticket["job"].get<std::int64_t>());
    for (int i = 0; i < 2400; ++i) {
      json j = Raw("GET", path, "", 200);
      if (j.value("status", "") == "succeeded" || j.value("status", "") == "failed") return j;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return {};
  }
  // Two visits of one place from the same viewpoint; the box was put there between them. Returns the begin keyframe
  // of the second visit.
  std::int64_t TwoVisitsWithABoxAdded() {
    sim::SettingScene s = sim::MakeSetting(sim::Setting::kTA, 4);
    const PinholeIntrinsics K = sim::KinectIntrinsics();
    const Eigen::Quaterniond q(s.X_WorldCameraA.linear());
    const json pose = {{"position", {s.X_WorldCameraA.translation().x(), s.X_WorldCameraA.translation().y(),
                                     s.X_WorldCameraA.translation().z()}},
                       {"orientation", {q.x(), q.y(), q.z(), q.w()}}};
    const json camera = {{"width", K.width}, {"height", K.height}, {"fx", K.fx}, {"fy", K.fy}, {"cx", K.cx}, {"cy", K.cy}};
    std::int64_t second_begin = 0;
    for (int visit = 0; visit < 2; ++visit) {
      sim::Scene scene = s.scene;
      if (visit == 0) sim::RemoveObject(scene, s.movable_ids.at(1));  // not there yet on the first visit
      const json opened = Call("POST", "/v1/maps/home/scenes",
                               json({{"camera", camera}, {"pose", pose}, {"stamp", 1'000'000'000'000LL * (visit + 1)}}), 201);
      const std::string base = "/v1/maps/home/scenes/" + std::to_string(opened["id"].get<std::int64_t>());
      for (int i = 0; i < 6; ++i) {
        const sim::Frame f = sim::Render(scene, K, s.X_WorldCameraA, sim::SensorModel{}, 77 + visit * 10 + i);
        auto r = client_->Post(base + "/frames?stamp=" + std::to_string(1'000'000'000'000LL * (visit + 1) + i * 33'000'000LL),
                               std::string(reinterpret_cast<const char*>(f.depth_mm.data()), f.depth_mm.size() * 2),
                               "application/octet-stream");
        EXPECT_TRUE(r && r->status == 200) << (r ? r->body : "");
        if (r && visit == 1 && i == 0) second_begin = json::parse(r->body)["keyframe"].get<std::int64_t>();
      }
      Raw("POST", base + ":close?wait_for_analysis=true", "{}", 200);
    }
    return second_begin;
  }
  // `per_class` samples of each class around the given bags of words (seeded noise, clipped at 0).
  static json Samples(const std::vector<std::pair<std::string, std::vector<double>>>& centres, const std::string& type,
                      int per_class, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> noise(0.0, 0.02);
    json samples = json::array();
    for (int i = 0; i < per_class; ++i) {
      for (const auto& [label, centre] : centres) {
        std::vector<double> bag(centre.size());
        for (std::size_t w = 0; w < bag.size(); ++w) bag[w] = std::max(0.0, centre[w] + noise(rng));
        samples.push_back({{"label", label}, {"features", {{type, bag}}}});
      }
    }
    return samples;
  }
  json Train(const std::string& name, const json& samples) {
    const json ticket = Call("POST", "/v1/classifiers",
                             json({{"name", name}, {"samples", samples}, {"rounds", 5}, {"folds", 0}, {"seed", 2},
                                   {"base", {{{"kind", "knn"}, {"k", 1}}, {{"kind", "dtree"}, {"max_depth", 2}}}}}),
                             202);
    return WaitJob(ticket);
  }

  testing::TempDir dir_;
  std::unique_ptr<testing::ServerProcess> server_;
  std::unique_ptr<httplib::Client> client_;
};

TEST_F(ObjectClassificationHttpTest, SegmentIsClassifiedOperatorLabelWinsWhereIsUsesItAndBadRequestsStoreNothing) {
  Call("POST", "/v1/maps", json({{"id", "home"}, {"name", "flat"}}), 201);
  const std::int64_t keyframe = TwoVisitsWithABoxAdded();
  ASSERT_GT(keyframe, 0);
  std::int64_t box = 0;
  const json added = Raw("GET", "/v1/maps/home/events?type=added", "", 200);
  for (const json& e : added["events"]) {
    if (e["instance"].is_number() && e["segment"].is_number()) box = e["instance"].get<std::int64_t>();
  }
  ASSERT_GT(box, 0) << "no added object with a segment";
  const std::string classify = "/v1/maps/home/instances/" + std::to_string(box) + ":classify";

  // The map's fpfh codebook, from the keyframe's features.
  Call("POST", "/v1/maps/home/keyframes/" + std::to_string(keyframe) + ":extract", json({{"types", {"fpfh"}}}), 200);
  ASSERT_EQ(WaitJob(Call("POST", "/v1/maps/home/codebooks", json({{"type", "fpfh"}, {"words", 6}, {"seed", 1}}), 202))
                .value("status", ""), "succeeded");

  // A first classifier (two arbitrary classes) shows the bag of words the server computes for the box's segment.
  const std::vector<double> flat(6, 1.0 / 6), spike = {1, 0, 0, 0, 0, 0};
  ASSERT_EQ(Train("probe", Samples({{"flat", flat}, {"spike", spike}}, "fpfh", 6, 1)).value("status", ""), "succeeded");
  const json probe = Call("POST", classify, json({{"classifier", "probe"}}), 200);
  ASSERT_TRUE(probe["features"]["fpfh"]["bag"].is_array()) << probe.dump();
  EXPECT_GT(probe["features"]["fpfh"]["count"].get<int>(), 0);
  EXPECT_GT(probe["points"].get<int>(), 100);
  EXPECT_EQ(probe["keyframe"], keyframe);  // the points came from the keyframe that saw the box appear
  const std::vector<double> bag = probe["features"]["fpfh"]["bag"].get<std::vector<double>>();
  ASSERT_EQ(bag.size(), 6u);
  ASSERT_TRUE(probe["event"].is_number());  // the probe's class is the first label the object shows
  // A classifier that calls the box 'unknown' with every vote (the rejection class, never shown as a label): the
  // object then shows no label, and no event is written (an event never names 'unknown').
  const std::vector<double> mirrored(bag.rbegin(), bag.rend());
  ASSERT_NE(mirrored, bag);
  ASSERT_EQ(Train("guard", Samples({{"unknown", bag}, {"plant", mirrored}}, "fpfh", 8, 5)).value("status", ""), "succeeded");
  const json guard = Call("POST", classify, json({{"classifier", "guard"}}), 200);
  EXPECT_EQ(guard["label"], "unknown") << guard.dump();
  EXPECT_EQ(guard["label_source"], "none") << guard.dump();
  EXPECT_TRUE(guard["labels"].empty()) << guard.dump();
  EXPECT_TRUE(guard["event"].is_null()) << guard.dump();
  // Trained on bags like the box's ("box") and on the mirror image of it ("plant"), a classifier names it a box.
  ASSERT_EQ(Train("objects", Samples({{"box", bag}, {"plant", mirrored}}, "fpfh", 8, 3)).value("status", ""), "succeeded");
  const json result = Call("POST", classify, json({{"classifier", "objects"}}), 200);
  std::printf("segment %s: %d points, %d fpfh features, bag %s; p(box) %.3f\n", result["segment"].dump().c_str(),
              result["points"].get<int>(), result["features"]["fpfh"]["count"].get<int>(),
              result["features"]["fpfh"]["bag"].dump().c_str(), result["distribution"]["box"].get<double>());
  EXPECT_EQ(result["label"], "box") << result.dump();
  EXPECT_GT(result["distribution"]["box"].get<double>(), 0.5);
  EXPECT_NEAR(result["distribution"]["box"].get<double>() + result["distribution"]["plant"].get<double>(), 1.0, 1e-9);
  EXPECT_EQ(result["source"], "classifier");
  EXPECT_TRUE(result["applied"].get<bool>());
  EXPECT_EQ(result["label_source"], "classifier");
  EXPECT_EQ(result["features"]["fpfh"]["bag"], probe["features"]["fpfh"]["bag"]);  // deterministic extraction
  // The new most probable class is a "labelled" event of the classifier; the same class again writes none.
  ASSERT_TRUE(result["event"].is_number()) << result.dump();
  const json labelled = Raw("GET", "/v1/maps/home/events?type=labelled&instance=" + std::to_string(box), "", 200);
  ASSERT_EQ(labelled["events"].size(), 2u) << labelled.dump();  // the probe's class, then "box"
  const json& last = labelled["events"].back();
  EXPECT_EQ(last["id"], result["event"]);
  EXPECT_EQ(last["detection"], "classifier");
  EXPECT_EQ(last["label"], "box");
  for (const json& e : labelled["events"]) EXPECT_NE(e["label"], "unknown");
  EXPECT_TRUE(Call("POST", classify, json({{"classifier", "objects"}}), 200)["event"].is_null());
  // The listing's label filter finds the object by the labels it shows (the classifier's: nobody named it).
  const auto listed = [&](const std::string& label) {
    std::vector<std::int64_t> ids;
    const json page = Raw("GET", "/v1/maps/home/instances?label=" + label, "", 200);
    for (const json& i : page["instances"]) ids.push_back(i["id"]);
    return ids;
  };
  EXPECT_EQ(listed("box"), std::vector<std::int64_t>{box});
  EXPECT_TRUE(listed("unknown").empty());
  const json instance = Raw("GET", "/v1/maps/home/instances/" + std::to_string(box), "", 200);
  EXPECT_EQ(instance["label_source"], "classifier");
  EXPECT_NEAR(instance["labels"]["box"].get<double>(), result["distribution"]["box"].get<double>(), 1e-9);
  EXPECT_EQ(instance["classification"]["classifier"], "objects");
  EXPECT_EQ(instance["classification"]["label"], "box");
  // Where-is uses the classifier's label when nobody named an object so.
  const json where = Raw("GET", "/v1/maps/home/where?label=box", "", 200);
  EXPECT_EQ(where["instance"], box);
  EXPECT_EQ(where["label_source"], "classifier");
  EXPECT_NEAR(where["label_probability"].get<double>(), result["distribution"]["box"].get<double>(), 1e-9);

  // Bad requests: clear errors, and the instance (labels and classification) stays as it is.
  const auto refused = [&](const std::string& path, const std::string& body, int status, const std::string& field) {
    const json e = Raw("POST", path, body, status);
    EXPECT_TRUE(e["error"]["code"].is_string()) << path << " " << body << " " << e.dump();
    if (!field.empty()) {
      EXPECT_EQ(e["error"]["field"], field) << path << " " << body << " " << e.dump();
    }
  };
  refused("/v1/maps/nowhere/instances/" + std::to_string(box) + ":classify", R"({"classifier":"objects"})", 404, "map");
  refused("/v1/maps/home/instances/999999:classify", R"({"classifier":"objects"})", 404, "instance");
  refused(classify, R"({"classifier":"nothing"})", 404, "classifier");
  refused(classify, "not json", 400, "");
  refused(classify, R"({"classifier":5})", 400, "classifier");
  refused(classify, R"({})", 400, "classifier");
  refused(classify, R"({"classifier":"objects","extra":1})", 400, "extra");
  refused(classify, R"({"classifier":"bad name!"})", 400, "classifier");
  refused(classify, R"({"classifier":"objects","keypoint_spacing_m":0})", 400, "keypoint_spacing_m");
  refused(classify, R"({"classifier":"objects","keypoint_spacing_m":"dense"})", 400, "keypoint_spacing_m");
  refused(classify, R"({"classifier":"objects","min_points":5})", 400, "min_points");
  refused(classify, R"({"classifier":"objects","min_points":1e12})", 400, "min_points");
  refused(classify, R"({"classifier":"objects","min_points":1000000})", 422, "instance");  // more than the segment has
  // A classifier whose feature type the server cannot extract from a segment, one of a type without a codebook in the
  // map, and one whose descriptor length is not the codebook's word count.
  ASSERT_EQ(Train("client_type", Samples({{"a", {1, 0}}, {"b", {0, 1}}}, "x_look", 4, 4)).value("status", ""), "succeeded");
  refused(classify, R"({"classifier":"client_type"})", 422, "classifier");
  ASSERT_EQ(Train("shot_words", Samples({{"a", flat}, {"b", spike}}, "shot", 4, 5)).value("status", ""), "succeeded");
  refused(classify, R"({"classifier":"shot_words"})", 422, "classifier");
  ASSERT_EQ(Train("short_words", Samples({{"a", {1, 0, 0}}, {"b", {0, 0, 1}}}, "fpfh", 4, 6)).value("status", ""), "succeeded");
  refused(classify, R"({"classifier":"short_words"})", 422, "classifier");
  // An object entered by hand has no segment; furniture is not an object.
  const json entered = Raw("POST", "/v1/maps/home/instances", R"({"kind":"object","label":"vase","position":[1,1,0.5]})", 201);
  refused("/v1/maps/home/instances/" + std::to_string(entered["id"].get<std::int64_t>()) + ":classify",
          R"({"classifier":"objects"})", 409, "instance");
  const json table = Raw("POST", "/v1/maps/home/instances", R"({"kind":"furniture","label":"table","position":[2,1,0]})", 201);
  refused("/v1/maps/home/instances/" + std::to_string(table["id"].get<std::int64_t>()) + ":classify",
          R"({"classifier":"objects"})", 422, "instance");
  EXPECT_EQ(Raw("GET", "/v1/maps/home/instances/" + std::to_string(box), "", 200), instance);
  EXPECT_TRUE(Raw("GET", "/v1/maps/home/instances/" + std::to_string(entered["id"].get<std::int64_t>()), "", 200)
                  ["classification"].is_null());

  // An operator names it: the classifier never overrides that, though its result is kept beside the label.
  Raw("POST", "/v1/maps/home/instances/" + std::to_string(box) + ":label", R"({"label":"Mug","source":"operator"})", 200);
  const json again = Call("POST", classify, json({{"classifier", "objects"}}), 200);
  EXPECT_EQ(again["label"], "box");
  EXPECT_FALSE(again["applied"].get<bool>());
  EXPECT_EQ(again["label_source"], "operator");
  EXPECT_EQ(again["labels"], json({{"mug", 1.0}}));
  const json named = Raw("GET", "/v1/maps/home/instances/" + std::to_string(box), "", 200);
  EXPECT_EQ(named["labels"], json({{"mug", 1.0}}));
  EXPECT_EQ(named["label_source"], "operator");
  EXPECT_EQ(named["classification"]["label"], "box");
  EXPECT_EQ(Raw("GET", "/v1/maps/home/where?label=mug", "", 200)["label_source"], "operator");
  Raw("GET", "/v1/maps/home/where?label=box", "", 404);  // the only box was named a mug by the operator
  EXPECT_TRUE(again["event"].is_null());  // not applied: no label event
  EXPECT_TRUE(listed("box").empty());
  EXPECT_EQ(listed("mug"), std::vector<std::int64_t>{box});
  // Sparser keypoints give the same segment fewer features.
  const json coarse = Call("POST", classify, json({{"classifier", "objects"}, {"keypoint_spacing_m", 0.06}}), 200);
  EXPECT_LT(coarse["features"]["fpfh"]["count"].get<int>(), again["features"]["fpfh"]["count"].get<int>());
  EXPECT_GT(coarse["features"]["fpfh"]["count"].get<int>(), 0);
  // Each classification is in the audit trail with the instance before and after: the first gave it the label box.
  bool gave_box = false;
  const json audit = Raw("GET", "/v1/audit?map=home&action=instance.classify&limit=1000", "", 200);
  for (const json& e : audit["entries"]) {
    if (e["resource"] == "instance=" + std::to_string(box) && e["status"] == 200 && e["after"]["labels"].contains("box") &&
        !e["before"]["labels"].contains("box")) {
      gave_box = true;
    }
  }
  EXPECT_TRUE(gave_box);
}

}  // namespace
}  // namespace anchordb
