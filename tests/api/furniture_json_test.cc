// The JSON edge of the furniture routes: strict parsing into typed requests (errors naming the field) and the
// documents clients see.
#include "api/furniture_json.h"

#include <gtest/gtest.h>

#include "schema/error.h"

namespace anchordb::api {
namespace furniture_json_test {

using services::FramePrior;

void ExpectError(const std::function<void()>& f, ErrorCode code, const std::string& field) {
  try {
    f();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), code) << e.what();
    EXPECT_EQ(e.field(), field) << e.what();
    return;
  }
  ADD_FAILURE() << "no error (expected one naming " << field << ")";
}

TEST(FurnitureJson, ParsesAGraphRequest) {
  const services::CreateGraphRequest r = ParseCreateGraph(Json::parse(R"({
    "viewpoint": {"position": [1, 2, 0.5], "heading_rad": 0.25},
    "furniture": [{"position": [4, 0], "extent": [1, 2], "yaw_rad": 0.1, "categories": {"sofa": 3, "couch": 1}},
                  {"id": "p", "position": [4, 2], "categories": {"plant": 1}}],
    "params": {"n_best": 7, "frame_prior": "uniform", "adaptation": false, "sigma": null}})"));
  EXPECT_EQ(r.viewpoint.position_m, Eigen::Vector2d(1, 2));
  EXPECT_EQ(r.viewpoint.heading_rad, 0.25);
  ASSERT_EQ(r.furniture.size(), 2u);
  EXPECT_FALSE(r.furniture[0].id);  // the service names it v1
  EXPECT_EQ(r.furniture[0].extent_m, Eigen::Vector2d(1, 2));
  ASSERT_EQ(r.furniture[0].categories.size(), 2u);
  EXPECT_EQ(r.furniture[0].categories[0].word, "couch");  // in key order, as the weights are summed
  EXPECT_EQ(r.furniture[1].id, "p");
  EXPECT_EQ(r.furniture[1].extent_m, Eigen::Vector2d::Zero());
  EXPECT_EQ(r.params.n_best, 7);
  EXPECT_EQ(r.params.frame_prior, FramePrior::kUniform);
  EXPECT_EQ(r.params.adaptation, false);
  EXPECT_FALSE(r.params.sigma);
  EXPECT_FALSE(r.params.edge_max_gap_m);
}

TEST(FurnitureJson, RefusesMalformedRequestsNamingTheField) {
  const auto create = [](const char* text) { return [text] { ParseCreateGraph(Json::parse(text)); }; };
  ExpectError(create(R"({"viewpoint": {"position": [0, 0], "heading_rad": 0}, "furniture": [], "extra": 1})"), ErrorCode::kInvalidArgument, "extra");
  ExpectError(create(R"({"furniture": []})"), ErrorCode::kInvalidArgument, "viewpoint");
  ExpectError(create(R"({"viewpoint": {"position": [0], "heading_rad": 0}, "furniture": []})"), ErrorCode::kInvalidArgument,
              "viewpoint.position");
  ExpectError(create(R"({"viewpoint": {"position": [0, 0], "heading_rad": 0}, "furniture": [], "params": 3})"),
              ErrorCode::kInvalidArgument, "params");
  ExpectError(create(R"({"viewpoint": {"position": [0, 0], "heading_rad": 0}, "furniture": [], "params": {"frame_prior": "x"}})"),
              ErrorCode::kInvalidArgument, "params.frame_prior");
  ExpectError(create(R"({"viewpoint": {"position": [0, 0], "heading_rad": 0}, "furniture": [{"position": [0, 0], "categories": {}}]})"),
              ErrorCode::kInvalidArgument, "furniture[0].categories");
  ExpectError(create(R"({"viewpoint": {"position": [0, 0], "heading_rad": 0}, "furniture": [{"position": [0, 0], "categories": {"sofa": "a"}}]})"),
              ErrorCode::kInvalidArgument, "furniture[0].categories.sofa");
  const auto describe = [](const char* text) { return [text] { ParseDescription(Json::parse(text), 20); }; };
  ExpectError(describe(R"({"text": "the plant", "relation": "left_of"})"), ErrorCode::kInvalidArgument, "text");
  ExpectError(describe(R"({"located": "plant", "reference": "sofa"})"), ErrorCode::kInvalidArgument, "relation");
  ExpectError(describe(R"({"txt": "the plant is left of the sofa"})"), ErrorCode::kInvalidArgument, "txt");
  ExpectError(describe(R"({"text": "the plant is left of the sofa"})"), ErrorCode::kInvalidArgument, "text");  // > 20
  ExpectError([] { ParseProduce(Json::parse(R"({"located": "a"})")); }, ErrorCode::kInvalidArgument, "reference");
  EXPECT_EQ(ParseDescription(Json::parse(R"({"text": "the plant"})"), 20).text, "the plant");
}

TEST(FurnitureJson, AnUtteranceAsTheClientSeesIt) {
  namespace g = engine::grounding;
  services::Utterance u;
  u.located = {"v1", "shelf", "shelf", 0.8};
  u.reference = {"v2", "sofa", "sofa", 0.9};
  u.relation = g::Relation::kRightOf;
  u.frame = g::Frame::kIntrinsic;
  u.probability = 0.6;
  u.alternatives = {{g::Relation::kRightOf, 0.6}, {g::Relation::kBehind, 0.4}};
  u.sentence = "the shelf is to the right of the sofa";
  const Json j = ToJson(u);
  EXPECT_EQ(j["relation"], "right_of");
  EXPECT_EQ(j["phrase"], "to the right of");
  EXPECT_EQ(j["frame"], "intrinsic");
  EXPECT_EQ(j["scheme"], "statistical");
  EXPECT_EQ(j["located"]["vertex"], "v1");
  EXPECT_EQ(j["alternatives"][1]["relation"], "behind");
}

}  // namespace
}  // namespace anchordb::api
