// The JSON edge of the job routes: a forgetting request parsed strictly (types and keys here, ranges by
// CheckForgetRequest of the forget job kind, which the route and the forget subcommand both apply), and the
// documents clients see. Suite names are lower case so that `ctest -R forget` selects them.
#include "api/job_json.h"

#include <gtest/gtest.h>

#include "schema/error.h"
#include "services/jobs/forget_job.h"

namespace anchordb::api {
namespace job_json_test {

constexpr std::int64_t kWallNs = 1'800'000'000'000'000'000;

Error ParseError(const std::string& text) {
  try {
    services::CheckForgetRequest(ParseForgetRequest(Json::parse(text)), kWallNs);
  } catch (const Error& e) {
    return e;
  }
  return Error(ErrorCode::kInternal, "no error for " + text);
}

TEST(forgetting_policy, ParsesDefaultsAndValidatesStrictly) {
  const storage::ForgetRequest defaults = ParseForgetRequest(Json::object());
  EXPECT_FALSE(defaults.dry_run);
  EXPECT_TRUE(defaults.policy.drop_superseded);
  EXPECT_EQ(defaults.policy.keyframe_max_age_s, 7 * 86400.0);
  EXPECT_EQ(defaults.policy.event_max_age_s, 30 * 86400.0);
  EXPECT_EQ(defaults.policy.keep_relevance_at_least, 0.5);
  EXPECT_FALSE(defaults.policy.vacuum);
  EXPECT_FALSE(defaults.now_ns);
  const storage::ForgetRequest r = ParseForgetRequest(Json::parse(
      R"({"policy": {"superseded_models": false, "keyframe_max_age_s": 60, "keep_relevance_at_least": 1,
          "event_max_age_s": null, "vacuum": true}, "dry_run": true, "now": "2026-11-22T10:00:00Z"})"));
  EXPECT_TRUE(r.dry_run);
  EXPECT_FALSE(r.policy.drop_superseded);
  EXPECT_EQ(r.policy.keyframe_max_age_s, 60.0);
  EXPECT_FALSE(r.policy.event_max_age_s);
  EXPECT_EQ(r.policy.keep_relevance_at_least, 1.0);
  EXPECT_TRUE(r.policy.vacuum);
  EXPECT_EQ(r.now_ns, json::ParseIso8601Ns("2026-11-22T10:00:00Z"));
  EXPECT_NO_THROW(services::CheckForgetRequest(r, kWallNs));

  struct Case {
    const char* body;
    ErrorCode code;
    const char* field;
  };
  const Case cases[] = {
      {R"({"policy": {"keyframe_max_age_s": -1}})", ErrorCode::kUnprocessable, "policy.keyframe_max_age_s"},
      {R"({"policy": {"event_max_age_s": -0.5}})", ErrorCode::kUnprocessable, "policy.event_max_age_s"},
      {R"({"policy": {"event_max_age_s": 1e12}})", ErrorCode::kUnprocessable, "policy.event_max_age_s"},
      {R"({"policy": {"keep_relevance_at_least": 1.5}})", ErrorCode::kUnprocessable, "policy.keep_relevance_at_least"},
      {R"({"policy": {"keep_relevance_at_least": -0.1}})", ErrorCode::kUnprocessable, "policy.keep_relevance_at_least"},
      {R"({"policy": {"keyframes": 1}})", ErrorCode::kInvalidArgument, "policy.keyframes"},
      {R"({"polcy": {}})", ErrorCode::kInvalidArgument, "polcy"},
      {R"({"policy": {"keyframe_max_age_s": "7d"}})", ErrorCode::kInvalidArgument, "policy.keyframe_max_age_s"},
      {R"({"policy": {"vacuum": 1}})", ErrorCode::kInvalidArgument, "policy.vacuum"},
      {R"({"policy": {"superseded_models": "yes"}})", ErrorCode::kInvalidArgument, "policy.superseded_models"},
      {R"({"policy": [1]})", ErrorCode::kInvalidArgument, "policy"},
      {R"({"dry_run": "true"})", ErrorCode::kInvalidArgument, "dry_run"},
      {R"({"now": "2099-01-01T00:00:00Z"})", ErrorCode::kUnprocessable, "now"},
      {R"({"now": "yesterday"})", ErrorCode::kInvalidArgument, "now"},
      {R"([1])", ErrorCode::kInvalidJson, ""},
  };
  for (const Case& c : cases) {
    const Error e = ParseError(c.body);
    EXPECT_EQ(e.code(), c.code) << c.body << ": " << e.what();
    EXPECT_EQ(e.field(), c.field) << c.body;
  }
}

TEST(forgetting_job_json, TicketsAndViewsAsTheClientSeesThem) {
  RegisterBuiltInJobDocumentWriters();
  const Json ticket = ToJson(services::JobTicket{7, "backup", std::nullopt, {storage::EncodeBackupRequest({"/b/x.sqlite"}), {}}});
  EXPECT_EQ(ticket, Json::parse(R"({"job": 7, "status": "queued", "kind": "backup", "map": null,
                                    "request": {"file": "/b/x.sqlite"}})"));
  services::JobView v;
  v.id = 3;
  v.kind = "forget";
  v.map = "home";
  v.status = services::JobStatus::kRunning;
  v.stage = "keyframes";
  v.progress = 0.5;
  services::ForgetRequest request;
  request.policy.event_max_age_s = std::nullopt;
  v.request = {storage::EncodeForgetRequest(request), {}};
  const Json j = ToJson(v);
  EXPECT_EQ(j["status"], "running");
  EXPECT_EQ(j["map"], "home");
  EXPECT_EQ(j["request"]["dry_run"], false);
  EXPECT_TRUE(j["request"]["policy"]["event_max_age_s"].is_null());
  EXPECT_EQ(j["request"]["policy"]["keyframe_max_age_s"], 7 * 86400.0);
  EXPECT_TRUE(j["result"].is_null());
  EXPECT_TRUE(j["error"].is_null());
  EXPECT_EQ(ParseBackupRequest(Json::parse(R"({"label": "nightly"})")).label, "nightly");
  EXPECT_THROW(ParseBackupRequest(Json::parse(R"({"lable": "nightly"})")), Error);
}

TEST(forgetting_job_json, OldRowsShowTheirTextAndUnreadableDocumentsSayWhy) {
  RegisterBuiltInJobDocumentWriters();
  services::JobView v;
  v.id = 5;
  v.kind = "forget";
  v.request = {{}, R"({"dry_run": true})"};                 // written before migration 0024
  v.result = services::JobDocument{"ADBB truncated", {}};    // a corrupt row
  Json j = ToJson(v);
  EXPECT_EQ(j["request"], Json::parse(R"({"dry_run": true})"));
  ASSERT_TRUE(j["result"].contains("unreadable"));
  EXPECT_NE(j["result"]["unreadable"].get<std::string>().find("job 5's result"), std::string::npos);
  v.kind = "no-such-kind";
  v.request = {storage::EncodeForgetRequest({}), {}};
  j = ToJson(v);
  EXPECT_NE(j["request"]["unreadable"].get<std::string>().find("no-such-kind"), std::string::npos);
}

}  // namespace
}  // namespace anchordb::api
