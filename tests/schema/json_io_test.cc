#include "schema/json_io.h"

#include <gtest/gtest.h>

#include "schema/error.h"

namespace anchordb::json {
namespace json_io_test {

ErrorCode CodeOf(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.code();
  }
  ADD_FAILURE() << "no error thrown";
  return ErrorCode::kInternal;
}

TEST(JsonIoTest, ParseObjectRejectsNonObjectsAndGarbage) {
  EXPECT_EQ(CodeOf([] { ParseObject(""); }), ErrorCode::kInvalidJson);
  EXPECT_EQ(CodeOf([] { ParseObject("{\"a\":"); }), ErrorCode::kInvalidJson);
  EXPECT_EQ(CodeOf([] { ParseObject("[1,2]"); }), ErrorCode::kInvalidJson);
  EXPECT_EQ(CodeOf([] { ParseObject("{\"x\": NaN}"); }), ErrorCode::kInvalidJson);
  EXPECT_EQ(ParseObject("{\"a\":1}")["a"], 1);
}

TEST(JsonIoTest, NumbersMustBeFiniteAndOfTheRightType) {
  // A literal that overflows a double is refused by the parser already; a non-finite value inside is refused too.
  EXPECT_EQ(CodeOf([] { ParseObject(R"({"big": 1e999})"); }), ErrorCode::kInvalidJson);
  Json j = ParseObject(R"({"s": "3", "ok": 2.5})");
  j["big"] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(CodeOf([&] { RequireFiniteNumber(j, "big"); }), ErrorCode::kInvalidArgument);
  EXPECT_EQ(CodeOf([&] { RequireFiniteNumber(j, "s"); }), ErrorCode::kInvalidArgument);
  EXPECT_EQ(CodeOf([&] { RequireFiniteNumber(j, "missing"); }), ErrorCode::kInvalidArgument);
  EXPECT_DOUBLE_EQ(RequireFiniteNumber(j, "ok"), 2.5);
}

TEST(JsonIoTest, PoseQuaternionIsNormalisedWithinToleranceElseRejected) {
  const Pose3 p = AsPose3(Json::parse(R"({"position":[1,2,3],"orientation":[0,0,0.7071,0.7071]})"), "pose");
  EXPECT_NEAR(p.orientation.norm(), 1.0, 1e-12);
  EXPECT_NEAR(p.YawRad(), M_PI / 2, 1e-3);
  try {
    AsPose3(Json::parse(R"({"position":[1,2,3],"orientation":[0,0,0,2]})"), "pose");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kUnprocessable);
    EXPECT_EQ(e.field(), "pose.orientation");
  }
  EXPECT_EQ(CodeOf([] { AsPose3(Json::parse(R"({"position":[1,2],"orientation":[0,0,0,1]})"), "pose"); }),
            ErrorCode::kInvalidArgument);
  EXPECT_EQ(CodeOf([] { AsPose3(Json::parse(R"({"position":[1,2,3],"orientation":[0,0,0,1],"x":1})"), "pose"); }),
            ErrorCode::kInvalidArgument);
}

TEST(JsonIoTest, StampsAsIntegersOrIso8601) {
  EXPECT_EQ(AsStampNs(Json(1700000000000000000LL), "stamp"), 1700000000000000000LL);
  EXPECT_EQ(AsStampNs(Json("1970-01-01T00:00:01.5Z"), "stamp"), 1500000000LL);
  EXPECT_EQ(AsStampNs(Json("2026-11-22T10:00:00+01:00"), "stamp"), AsStampNs(Json("2026-11-22T09:00:00Z"), "stamp"));
  EXPECT_EQ(CodeOf([] { AsStampNs(Json("yesterday"), "stamp"); }), ErrorCode::kInvalidArgument);
  EXPECT_EQ(CodeOf([] { AsStampNs(Json(-5), "stamp"); }), ErrorCode::kInvalidArgument);
}

TEST(JsonIoTest, PolygonsLimitsAndShape) {
  const Json ok = Json::parse("[[[0,0],[1,0],[1,1]]]");
  EXPECT_EQ(AsPolygons(ok, "stimulus", 4, 8).size(), 1u);
  EXPECT_EQ(CodeOf([&] { AsPolygons(ok, "stimulus", 0, 8); }), ErrorCode::kPayloadTooLarge);
  EXPECT_EQ(CodeOf([&] { AsPolygons(ok, "stimulus", 4, 2); }), ErrorCode::kPayloadTooLarge);
  EXPECT_EQ(CodeOf([] { AsPolygons(Json::parse("[[[0,0],[1,0]]]"), "s", 4, 8); }), ErrorCode::kUnprocessable);
  EXPECT_EQ(CodeOf([] { AsPolygons(Json::parse("[[[0,0],[1,\"x\"],[1,1]]]"), "s", 4, 8); }), ErrorCode::kInvalidArgument);
}

TEST(JsonIoTest, IdsAndUnknownKeys) {
  EXPECT_TRUE(IsValidId("kitchen-table_1.v2"));
  EXPECT_FALSE(IsValidId(""));
  EXPECT_FALSE(IsValidId(".hidden"));
  EXPECT_FALSE(IsValidId("a/b"));
  EXPECT_FALSE(IsValidId(std::string(65, 'a')));
  EXPECT_EQ(CodeOf([] { RejectUnknownKeys(Json::parse(R"({"id":1,"nmae":2})"), {"id", "name"}); }),
            ErrorCode::kInvalidArgument);
}

TEST(JsonIoTest, LogOddsParamsValidated) {
  EXPECT_DOUBLE_EQ(AsLogOddsParams(Json::object(), "log_odds").hit_probability, 0.7);
  EXPECT_EQ(CodeOf([] { AsLogOddsParams(Json::parse(R"({"hit":0.4})"), "l"); }), ErrorCode::kUnprocessable);
  EXPECT_EQ(CodeOf([] { AsLogOddsParams(Json::parse(R"({"clamp_min":0.6})"), "l"); }), ErrorCode::kUnprocessable);
}

}  // namespace
}  // namespace anchordb::json
