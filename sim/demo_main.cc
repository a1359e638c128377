// anchordb-demo: the lost-key scenario (thesis 1.4, 3.5.2) against a running server; prints what happens, the
// change events and the answer to "where are my keys?". Used by scripts/demo.
#include <Eigen/Core>
#include <httplib.h>

#include <chrono>
#include <cstring>
#include <iostream>

#include "sim/lost_key_scenario.h"

int main(int argc, char** argv) {
  std::string host = "127.0.0.1", token, map;
  int port = 8765;
  std::uint64_t seed = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::cerr << "anchordb-demo: " << arg << " needs a value\n";
        std::exit(2);
      }
      return argv[++i];
    };
    if (arg == "--host") host = value();
    else if (arg == "--port") port = std::stoi(value());
    else if (arg == "--token") token = value();
    else if (arg == "--map") map = value();
    else if (arg == "--seed") seed = std::stoull(value());
    else {
      std::cerr << "usage: anchordb-demo [--host 127.0.0.1] [--port 8765] [--token T] [--map ID] [--seed N]\n";
      return 2;
    }
  }
  if (map.empty()) {
    map = "lost-key-demo-" + std::to_string(std::chrono::duration_cast<std::chrono::seconds>(
                                                 std::chrono::system_clock::now().time_since_epoch()).count());
  }
  httplib::Client client(host, port);
  client.set_read_timeout(60, 0);
  if (!token.empty()) client.set_bearer_token_auth(token);
  anchordb::sim::LostKeyOptions options;
  options.seed = seed;
  options.map = map;
  options.log = [](const std::string& line) { std::cout << line << std::endl; };
  std::cout << "lost-key demo on map '" << map << "' at http://" << host << ":" << port << "\n";
  try {
    const auto result = anchordb::sim::RunLostKeyScenario(client, options);
    std::cout << "\nchange events:\n";
    for (const auto& e : result.events) {
      std::cout << "  #" << e["id"] << " " << e["type"].get<std::string>() << " (" << e["detection"].get<std::string>() << ")";
      if (e["details"].contains("segment")) {
        const auto& c = e["details"]["segment"]["centroid_m"];
        std::cout << " at (" << c[0].get<double>() << ", " << c[1].get<double>() << ", " << c[2].get<double>() << ")";
      }
      if (!e["label"].is_null()) std::cout << " label '" << e["label"].get<std::string>() << "'";
      std::cout << "\n     " << e["explanation"].get<std::string>() << "\n";
    }
    std::cout << "\nQ: where are my keys?\nA: " << result.where.value("sentence", result.where.dump()) << "\n";
    std::cout << "   (confidence " << result.where.value("confidence", 0.0) << ", evidence keyframes "
              << result.where.value("evidence", nlohmann::json::array()).dump() << ")\n";
    std::cout << "Q: and where were they before the person brought them here?\nA: "
              << result.past_where.value("sentence", result.past_where.dump()) << "\n";
    const auto p = result.where.value("position_m", std::vector<double>{0, 0, 0});
    const double error = (Eigen::Vector3d(p[0], p[1], p[2]) - result.keys_true_m).norm();
    std::cout << "\n(the keys really are at (" << result.keys_true_m.x() << ", " << result.keys_true_m.y() << ", "
              << result.keys_true_m.z() << "); the answer is " << error << " m from there)\n";
    return result.where.value("sentence", std::string()).find(result.keys_furniture) != std::string::npos ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "anchordb-demo: " << e.what() << "\n";
    return 1;
  }
}
