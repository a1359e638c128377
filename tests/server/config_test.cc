#include "server/config.h"

#include <gtest/gtest.h>

#include <fstream>

#include "tests/support/temp_dir.h"

namespace anchordb::server {
namespace config_test {

TEST(ConfigTest, DefaultsFileEnvironmentFlagsInIncreasingPrecedence) {
  testing::TempDir dir;
  const std::string file = dir.File("c.json");
  std::ofstream(file) << R"({"port": 9000, "threads": 3, "db": "from-file.sqlite"})";
  const Config c = LoadConfig({"--config", file, "--threads=5"}, {{"ANCHORDB_PORT", "9100"}, {"ANCHORDB_THREADS", "4"}});
  EXPECT_EQ(c.server.db, "from-file.sqlite");
  EXPECT_EQ(c.server.port, 9100);
  EXPECT_EQ(c.server.threads, 5);
  EXPECT_EQ(c.server.bind, "127.0.0.1");
  EXPECT_EQ(LoadConfig({"--busy-timeout-ms", "77"}, {}).server.busy_timeout_ms, 77);
}

TEST(ConfigTest, UnknownKeysAndBadValuesAreErrors) {
  testing::TempDir dir;
  const std::string file = dir.File("c.json");
  std::ofstream(file) << R"({"prot": 9000})";
  EXPECT_THROW(LoadConfig({"--config", file}, {}), std::invalid_argument);
  EXPECT_THROW(LoadConfig({"--nonsense=1"}, {}), std::invalid_argument);
  EXPECT_THROW(LoadConfig({"--port=70000"}, {}), std::invalid_argument);
  EXPECT_THROW(LoadConfig({"--port=80.5"}, {}), std::invalid_argument);
  EXPECT_THROW(LoadConfig({"--threads=many"}, {}), std::invalid_argument);
  EXPECT_THROW(LoadConfig({"--auth=maybe"}, {}), std::invalid_argument);
  EXPECT_THROW(LoadConfig({"--port"}, {}), std::invalid_argument);
  EXPECT_THROW(LoadConfig({"stray"}, {}), std::invalid_argument);
  EXPECT_THROW(LoadConfig({}, {{"ANCHORDB_PORT", "x"}}), std::invalid_argument);
}

TEST(ConfigTest, EverySettingIsDescribedAndServed) {
  Config config;
  const auto doc = SettingsJson(config);
  ASSERT_EQ(doc["settings"].size(), BindSettings(config).entries().size());
  for (const auto& s : doc["settings"]) {
    EXPECT_FALSE(s["description"].get<std::string>().empty()) << s["name"];
    EXPECT_TRUE(s.contains("value"));
  }
  EXPECT_NE(SettingsHelp().find("--viewpoint_dilation_m"), std::string::npos);
}

TEST(ConfigTest, LoopbackDetection) {
  EXPECT_TRUE(IsLoopback("127.0.0.1"));
  EXPECT_TRUE(IsLoopback("127.3.4.5"));
  EXPECT_TRUE(IsLoopback("::1"));
  EXPECT_TRUE(IsLoopback("localhost"));
  EXPECT_FALSE(IsLoopback("0.0.0.0"));
  EXPECT_FALSE(IsLoopback("192.168.1.4"));
}

}  // namespace
}  // namespace anchordb::server
