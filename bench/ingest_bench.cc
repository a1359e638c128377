// Frame ingest over loopback HTTP (SPEC section 7: >= 60 frames/s per connection, durable): opens a scene model on a
// running server and posts rendered 640x480 frames over one keep-alive connection, as PNG and as raw bytes.
//   anchordb_ingest_bench --port P [--frames N] [--journal on|off]
// prints one JSON line per encoding; --journal only labels the lines (the server's scene_frame_journal decides).
#include "engine/scene/depth_image.h"  // Eigen before httplib.h (see api/http_api.h)
#include "sim/apartment.h"
#include "sim/renderer.h"

#include <httplib.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

using namespace anchordb;

int main(int argc, char** argv) {
  int port = 0, frames = 120;
  std::string journal = "on";
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::strcmp(argv[i], "--port") == 0) port = std::atoi(argv[i + 1]);
    if (std::strcmp(argv[i], "--frames") == 0) frames = std::atoi(argv[i + 1]);
    if (std::strcmp(argv[i], "--journal") == 0) journal = argv[i + 1];
  }
  if (port <= 0 || frames <= 0 || (journal != "on" && journal != "off")) {
    std::fprintf(stderr, "usage: anchordb_ingest_bench --port P [--frames N] [--journal on|off]\n");
    return 2;
  }
  const sim::SettingScene s = sim::MakeSetting(sim::Setting::kTA, 1);
  const PinholeIntrinsics K = sim::KinectIntrinsics();
  std::vector<std::string> png, raw;
  for (int i = 0; i < 10; ++i) {
    const sim::Frame f = sim::Render(s.scene, K, s.X_WorldCameraA, sim::SensorModel{}, 7 + i);
    png.push_back(engine::EncodeDepthPng(f.depth_mm, K.width, K.height));
    raw.emplace_back(reinterpret_cast<const char*>(f.depth_mm.data()), f.depth_mm.size() * 2);
  }
  httplib::Client client("127.0.0.1", port);
  client.set_keep_alive(true);
  client.set_tcp_nodelay(true);
  client.Post("/v1/maps", R"({"id":"ingest"})", "application/json");
  const Eigen::Quaterniond q(s.X_WorldCameraA.linear());
  const Eigen::Vector3d t = s.X_WorldCameraA.translation();
  char body[512];
  std::snprintf(body, sizeof(body),
                R"({"camera":{"width":640,"height":480,"fx":%f,"fy":%f,"cx":%f,"cy":%f},"pose":{"position":[%f,%f,%f],"orientation":[%f,%f,%f,%f]}})",
                K.fx, K.fy, K.cx, K.cy, t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w());
  for (const char* encoding : {"png", "raw"}) {
    auto opened = client.Post("/v1/maps/ingest/scenes", body, "application/json");
    if (!opened || opened->status != 201) {
      std::fprintf(stderr, "cannot open a scene model: %s\n", opened ? opened->body.c_str() : "no response");
      return 1;
    }
    const std::string id = opened->body.substr(opened->body.find("\"id\":") + 5, opened->body.find(',', opened->body.find("\"id\":")) - opened->body.find("\"id\":") - 5);
    const std::string path = "/v1/maps/ingest/scenes/" + id + "/frames";
    const bool is_png = std::strcmp(encoding, "png") == 0;
    std::size_t bytes = 0;
    std::vector<double> frame_ms;
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < frames; ++i) {
      const std::string& b = is_png ? png[i % png.size()] : raw[i % raw.size()];
      bytes += b.size();
      const auto sent = std::chrono::steady_clock::now();
      auto r = client.Post(path, b, is_png ? "image/png" : "application/octet-stream");
      frame_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - sent).count());
      if (!r || r->status != 200) {
        std::fprintf(stderr, "frame %d failed: %s\n", i, r ? r->body.c_str() : "no response");
        return 1;
      }
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::sort(frame_ms.begin(), frame_ms.end());
    const double p99_ms = frame_ms[std::min(frame_ms.size() - 1, static_cast<std::size_t>(0.99 * frame_ms.size()))];
    std::printf("{\"encoding\":\"%s\",\"journal\":\"%s\",\"frames\":%d,\"seconds\":%.3f,\"frames_per_s\":%.1f,"
                "\"ms_per_frame\":%.3f,\"p99_ms\":%.3f,\"max_ms\":%.3f,\"mean_body_bytes\":%zu}\n",
                encoding, journal.c_str(), frames, seconds, frames / seconds, 1000.0 * seconds / frames, p99_ms,
                frame_ms.back(), bytes / frames);
  }
  return 0;
}
