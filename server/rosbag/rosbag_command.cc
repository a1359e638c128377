// `anchordb import rosbag` command line: flags -> RosbagImportOptions -> ImportRosbag.
#include <filesystem>
#include <iostream>
#include <stdexcept>

#include "schema/error.h"
#include "schema/json_io.h"
#include "server/rosbag/rosbag_import.h"

namespace anchordb::server {
namespace {

int PositiveCount(const std::string& text, const std::string& flag) {
  std::size_t used = 0;
  int v = 0;
  try {
    v = std::stoi(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || v < 1) throw std::invalid_argument(flag + ": expected a whole number >= 1, got '" + text + "'");
  return v;
}

}  // namespace

int ImportRosbagCommand(const std::vector<std::string>& args, const std::map<std::string, std::string>& environment) {
  RosbagImportOptions o;
  std::string db, preset, depth_topic, info_topic, map_frame, every;
  std::vector<std::string> rest;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (TakeOption(args, i, "--db", db)) {
      rest.push_back("--db=" + db);
      continue;
    }
    if (TakeOption(args, i, "--bag", o.bag) || TakeOption(args, i, "--map", o.map) ||
        TakeOption(args, i, "--preset", preset) || TakeOption(args, i, "--depth-topic", depth_topic) ||
        TakeOption(args, i, "--info-topic", info_topic) || TakeOption(args, i, "--map-frame", map_frame) ||
        TakeOption(args, i, "--every", every) || TakeOption(args, i, "--grid-topic", o.topics.grid) ||
        TakeOption(args, i, "--mask-topic", o.topics.mask) || TakeOption(args, i, "--grid-layer", o.grid_layer)) {
      continue;
    }
    if (args[i] == "--no-merge") o.merge = false;
    else rest.push_back(args[i]);
  }
  if (o.bag.empty()) throw std::invalid_argument("import rosbag needs --bag FILE.bag");
  if (o.map.empty()) throw std::invalid_argument("import rosbag needs --map ID");
  if (!preset.empty()) {
    if (preset != "tum") throw std::invalid_argument("--preset: unknown '" + preset + "' (known: tum)");
    const RosbagTopics tum = TumPresetTopics();
    o.topics.depth = tum.depth, o.topics.info = tum.info, o.topics.map_frame = tum.map_frame;
  }
  if (!depth_topic.empty()) o.topics.depth = depth_topic;
  if (!info_topic.empty()) o.topics.info = info_topic;
  if (!map_frame.empty()) o.topics.map_frame = map_frame;
  if (!every.empty()) o.topics.every = PositiveCount(every, "--every");
  if (!std::filesystem::is_regular_file(o.bag)) throw std::invalid_argument("--bag: no file " + o.bag);
  try {
    json::CheckId(o.map, "map");
  } catch (const Error& e) {
    throw std::invalid_argument(std::string("--map: ") + e.what());
  }
  const Config config = LoadConfig(rest, environment);
  RequireExistingDatabase(config.server.db);
  ImportRosbag(config, o, std::cout);
  return 0;
}

}  // namespace anchordb::server
