// The OpenAPI document describes exactly the registered routes, with the documented roles and error responses.
#include <gtest/gtest.h>

#include <set>

#include "api/http_api.h"
#include "api/audit_routes.h"
#include "api/request_limits.h"
#include "api/routes.h"
#include "storage/store.h"
#include "tests/support/temp_dir.h"

namespace anchordb::api {
namespace openapi_test {

// The route table of every capability, on a fresh database.
class OpenApiTest : public ::testing::Test {
 protected:
  OpenApiTest() { RegisterAllRoutes(api.router(), capabilities); }
  static storage::StoreOptions Options(const testing::TempDir& dir) {
    storage::StoreOptions so;
    so.path = dir.File("db.sqlite");
    return so;
  }
  testing::TempDir dir;
  storage::Store store{Options(dir)};
  services::Capabilities capabilities{store, {}};
  HttpApi api{{}};
};

TEST_F(OpenApiTest, DocumentMatchesRouteTable) {
  const Json doc = Json::parse(HttpApi::OpenApiDocument());
  ASSERT_TRUE(doc.contains("paths"));
  std::set<std::string> registered, documented;
  for (const Route& r : api.routes()) {
    std::string method = r.method;
    for (char& c : method) c = static_cast<char>(std::tolower(c));
    registered.insert(method + " " + r.pattern);
    ASSERT_TRUE(doc["paths"].contains(r.pattern)) << "undocumented path " << r.pattern;
    const Json& path = doc["paths"][r.pattern];
    ASSERT_TRUE(path.contains(method)) << "undocumented operation " << r.method << " " << r.pattern;
    const Json& op = path[method];
    EXPECT_EQ(op.value("x-anchordb-role", ""), RoleName(r.role)) << r.pattern;
    EXPECT_FALSE(op.value("summary", "").empty()) << r.pattern;
    EXPECT_TRUE(op["responses"].contains("500")) << r.pattern;
    if (r.role != Role::kPublic) {
      EXPECT_TRUE(op["responses"].contains("401")) << r.pattern;
      EXPECT_TRUE(op["responses"].contains("403")) << r.pattern;
    }
    // Every {param} of the pattern is documented as a path parameter.
    for (std::size_t pos = r.pattern.find('{'); pos != std::string::npos; pos = r.pattern.find('{', pos + 1)) {
      const std::string name = r.pattern.substr(pos + 1, r.pattern.find('}', pos) - pos - 1);
      bool found = false;
      for (const Json& p : op.value("parameters", Json::array())) found = found || (p["name"] == name && p["in"] == "path");
      EXPECT_TRUE(found) << r.pattern << " lacks path parameter " << name;
    }
  }
  for (const auto& [path, ops] : doc["paths"].items()) {
    for (const auto& [method, op] : ops.items()) documented.insert(method + " " + path);
  }
  EXPECT_EQ(registered, documented);
}

// Every string of a request body has a maxLength (or an enum, or is binary) and every array a maxItems, and the
// figures are those the server enforces (api/request_limits.h and the settings' defaults).
const Json& Resolve(const Json& doc, const Json& schema) {
  if (!schema.contains("$ref")) return schema;
  const std::string ref = schema["$ref"];  // "#/components/schemas/Name"
  return doc["components"]["schemas"][ref.substr(ref.rfind('/') + 1)];
}

void ExpectBounded(const Json& doc, const Json& schema_in, const std::string& where) {
  const Json& schema = Resolve(doc, schema_in);
  const std::string type = schema.value("type", "");
  if (type == "string") {
    EXPECT_TRUE(schema.contains("maxLength") || schema.contains("enum") || schema.value("format", "") == "binary")
        << where << " has no maxLength";
  }
  if (type == "array") {
    EXPECT_TRUE(schema.contains("maxItems")) << where << " has no maxItems";
    if (schema.contains("items")) ExpectBounded(doc, schema["items"], where + "[]");
  }
  if (schema.contains("properties")) {
    for (const auto& [name, sub] : schema["properties"].items()) ExpectBounded(doc, sub, where + "." + name);
  }
  if (schema.contains("additionalProperties") && schema["additionalProperties"].is_object()) {
    EXPECT_TRUE(schema.contains("maxProperties")) << where << " has no maxProperties";
    ExpectBounded(doc, schema["additionalProperties"], where + ".*");
  }
}

TEST_F(OpenApiTest, EveryRequestStringAndArrayHasItsLimit) {
  const Json doc = Json::parse(HttpApi::OpenApiDocument());
  for (const auto& [path, ops] : doc["paths"].items()) {
    for (const auto& [method, op] : ops.items()) {
      for (const Json& p : op.value("parameters", Json::array())) {
        const Json& schema = p["schema"];
        if (schema.value("type", "") != "string") continue;
        ASSERT_TRUE(schema.contains("maxLength")) << method << " " << path << " parameter " << p["name"];
        EXPECT_LE(schema["maxLength"].get<std::size_t>(), limits::kQueryValueLength) << path << " " << p["name"];
      }
      if (!op.contains("requestBody")) continue;
      for (const auto& [type, content] : op["requestBody"]["content"].items()) {
        if (type == "application/json") {
          EXPECT_TRUE(content.contains("schema")) << method << " " << path << " has an undocumented JSON body";
        }
        if (content.contains("schema")) ExpectBounded(doc, content["schema"], method + " " + path);
      }
    }
  }
}

TEST_F(OpenApiTest, DocumentedLimitsAreTheEnforcedOnes) {
  const Json doc = Json::parse(HttpApi::OpenApiDocument());
  const Json& s = doc["components"]["schemas"];
  EXPECT_EQ(s["LabelRequest"]["properties"]["label"]["maxLength"], limits::kLabelLength);
  EXPECT_EQ(s["InstanceCreate"]["properties"]["label"]["maxLength"], limits::kLabelLength);
  EXPECT_EQ(s["LabelPaint"]["properties"]["label"]["maxLength"], limits::kLabelLength);
  EXPECT_EQ(s["MapCreate"]["properties"]["name"]["maxLength"], limits::kNameLength);
  EXPECT_EQ(s["MapCreate"]["properties"]["id"]["maxLength"], limits::kIdLength);
  EXPECT_EQ(s["LayerCreate"]["properties"]["operands"]["maxItems"], limits::kFusedOperands);
  const Json& piece = s["FurnitureGraphCreate"]["properties"]["furniture"]["items"]["properties"];
  EXPECT_EQ(piece["categories"]["maxProperties"], limits::kCategoriesPerPiece);
  EXPECT_EQ(piece["categories"]["propertyNames"]["maxLength"], limits::kCategoryWordLength);
  EXPECT_EQ(s["FurnitureDescription"]["properties"]["located"]["maxLength"], limits::kDescriptionWordLength);
  const services::ServiceLimits grid;
  EXPECT_EQ(s["Observation"]["properties"]["stimulus"]["maxItems"], grid.max_polygons);
  EXPECT_EQ(s["Observation"]["properties"]["stimulus"]["items"]["maxItems"], grid.max_polygon_vertices);
  const services::FurnitureSettings furniture;
  EXPECT_EQ(s["FurnitureGraphCreate"]["properties"]["furniture"]["maxItems"], furniture.max_furniture);
  EXPECT_EQ(s["FurnitureDescription"]["properties"]["text"]["maxLength"], furniture.max_text_length);
}

// Every audited action names a registered route, and its snapshot a registered GET route.
TEST_F(OpenApiTest, AuditedActionsNameRegisteredRoutes) {
  std::set<std::string> routes;
  for (const Route& r : api.routes()) routes.insert(r.method + " " + r.pattern);
  for (const AuditedAction& a : AuditedActions()) {
    EXPECT_TRUE(routes.count(std::string(a.method) + " " + a.pattern)) << a.action;
    if (a.snapshot_pattern) {
      EXPECT_TRUE(routes.count(std::string("GET ") + a.snapshot_pattern)) << a.action;
    }
  }
}

}  // namespace
}  // namespace anchordb::api
