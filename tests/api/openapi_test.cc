// The OpenAPI document describes exactly the registered routes, with the documented roles and error responses.
#include <gtest/gtest.h>

#include <set>

#include "api/http_api.h"
#include "api/routes.h"
#include "storage/store.h"
#include "tests/support/temp_dir.h"

namespace anchordb::api {
namespace {

TEST(OpenApiTest, DocumentMatchesRouteTable) {
  testing::TempDir dir;
  storage::StoreOptions so;
  so.path = dir.File("db.sqlite");
  storage::Store store(so);
  services::Capabilities capabilities(store, {});
  HttpApi api({});
  RegisterAllRoutes(api.router(), capabilities);
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

}  // namespace
}  // namespace anchordb::api
