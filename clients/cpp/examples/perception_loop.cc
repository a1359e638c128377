// A perception component's loop: open a scene model at the camera's pose, post depth frames from its own uint16
// buffer (a wall, then an object put down in front of it), close the observation and print the change events the
// server found. Usage: perception_loop [--host H] [--port P] [--token T] [--map M] [--frames N]
#include <anchordb/client.h>

#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  std::string host = "127.0.0.1", token, map = "example";
  int port = 8765, frames = 40;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "--host") host = v;
    else if (a == "--port") port = std::stoi(v);
    else if (a == "--token") token = v;
    else if (a == "--map") map = v;
    else if (a == "--frames") frames = std::stoi(v);
  }
  namespace ac = anchordb::client;
  try {
    ac::Client client(host, port, token);
    try {
      client.CreateMap(map);
    } catch (const ac::ApiError& e) {
      if (e.code() != "conflict") throw;  // the map exists already: use it
    }
    // A 160x120 depth camera 1 m above the floor at the map origin, looking along the map's x axis (optical frame:
    // z forward = map x, x right = map -y, y down = map -z).
    const ac::Camera camera{160, 120, 140.0, 140.0, 79.5, 59.5};
    const ac::Pose pose{{0.0, 0.0, 1.0}, {-0.5, 0.5, -0.5, 0.5}};
    const ac::Scene scene = client.OpenScene(map, camera, pose);
    std::cout << "scene " << scene.id << " opened\n";
    std::vector<std::uint16_t> depth_mm(static_cast<std::size_t>(camera.width) * camera.height);
    const std::int64_t start_ns = 1'767'225'600'000'000'000;
    for (int f = 0; f < frames; ++f) {
      const bool object = f >= frames / 2;  // halfway through, something is put down in front of the wall
      for (int v = 0; v < camera.height; ++v) {
        for (int u = 0; u < camera.width; ++u) {
          const bool in_object = object && u >= 60 && u < 100 && v >= 50 && v < 90;
          depth_mm[static_cast<std::size_t>(v) * camera.width + u] = in_object ? 1800 : 2500;
        }
      }
      const ac::FrameResult r = client.PostDepthFrame(map, scene.id, depth_mm.data(), camera.width, camera.height,
                                                      start_ns + f * 33'000'000LL);
      if (r.keyframe) std::cout << "frame " << f << " stored keyframe " << *r.keyframe << "\n";
    }
    const ac::Json closed = client.CloseScene(map, scene.id, /*wait_for_analysis=*/true);
    std::cout << "closed: end keyframe " << closed.value("keyframe", ac::Json()).dump() << "\n";
    const std::vector<ac::Event> events = client.Events(map);
    for (const ac::Event& e : events) {
      std::cout << "event " << e.id << " " << e.type << " (" << e.detection << ") instance "
                << (e.instance ? std::to_string(*e.instance) : "-") << ": " << e.explanation << "\n";
    }
    std::cout << events.size() << " events\n";
    return events.empty() ? 1 : 0;
  } catch (const ac::ApiError& e) {
    std::cerr << "perception_loop: the server refused: " << e.status() << " " << e.code() << " " << e.message()
              << (e.field().empty() ? "" : " (field " + e.field() + ")") << "\n";
  } catch (const std::exception& e) {
    std::cerr << "perception_loop: " << e.what() << "\n";
  }
  return 2;
}
