// anchordb_http_peer: the HTTP benchmark's peer (SPEC section 7, "cpp-httplib's bare handler for HTTP").
// Serves every GET with one fixed JSON body from a bare cpp-httplib handler with cpp-httplib's own serving (a
// ThreadPool of --threads workers, one per keep-alive connection; keep-alive max count 100000, read timeout 10 s), so
// that wrk against it and against `anchordb serve` in the same run shows what anchordb's routing, auth, metrics,
// SQLite read and fair serving (server/http_serving.h: a reactor and a pool that serves requests) add on top of the
// HTTP library. With wrk's 16 connections below 32 workers, the peer's one-worker-per-connection never starves.
//
//   anchordb_http_peer [--bind 127.0.0.1] [--port 0] [--threads 32] [--body_bytes 400] [--tcp_nodelay true]
//
// --threads and --tcp_nodelay default to what anchordb uses (32 workers, TCP_NODELAY on); with TCP_NODELAY
// off, each response (headers and body written separately) meets Nagle + delayed ACK on keep-alive connections.
//
// Prints "anchordb_http_peer listening on http://<bind>:<port> ..." on stdout once bound (port 0 = any free
// port), stops on SIGINT/SIGTERM.
#include <signal.h>

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <thread>

#include <httplib.h>

namespace {

// A layer-metadata-like JSON object padded to `bytes` bytes (at least the unpadded object).
std::string FixedBody(std::size_t bytes) {
  std::string body =
      R"({"map":"home","name":"occupancy","kind":"occupancy","geometry":{"width_cells":500,"height_cells":500,)"
      R"("resolution_m":0.05,"origin":[-12.5,-12.5,0.0]},"map_server":{"image":"map.pgm","negate":0,)"
      R"("occupied_thresh":0.65,"free_thresh":0.196,"mode":"trinary"},"revision":1,)"
      R"("created":"2024-06-01T00:00:00Z","updated":"2024-06-01T00:00:00Z","padding":")";
  const std::string tail = "\"}";
  while (body.size() + tail.size() < bytes) body += 'x';
  return body + tail;
}

bool ParseInt(const std::string& text, long lo, long hi, long& out) {
  char* end = nullptr;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || v < lo || v > hi) return false;
  out = v;
  return true;
}

int Usage() {
  std::cerr << "usage: anchordb_http_peer [--bind 127.0.0.1] [--port 0] [--threads 8] [--body_bytes 400] "
               "[--tcp_nodelay true]\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string bind = "127.0.0.1";
  long port = 0, threads = 32, body_bytes = 400;
  bool tcp_nodelay = true;
  for (int i = 1; i < argc; ++i) {
    std::string flag = argv[i], value;
    if (const auto eq = flag.find('='); eq != std::string::npos) {
      value = flag.substr(eq + 1);
      flag = flag.substr(0, eq);
    } else if (i + 1 < argc) {
      value = argv[++i];
    } else {
      return Usage();
    }
    bool ok = true;
    if (flag == "--bind") bind = value;
    else if (flag == "--port") ok = ParseInt(value, 0, 65535, port);
    else if (flag == "--threads") ok = ParseInt(value, 1, 1024, threads);
    else if (flag == "--body_bytes") ok = ParseInt(value, 1, 1 << 20, body_bytes);
    else if (flag == "--tcp_nodelay") ok = (value == "true" || value == "false") && ((tcp_nodelay = value == "true"), true);
    else ok = false;
    if (!ok) return Usage();
  }

  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  signal(SIGPIPE, SIG_IGN);

  const std::string body = FixedBody(static_cast<std::size_t>(body_bytes));
  httplib::Server server;
  server.new_task_queue = [threads] { return new httplib::ThreadPool(static_cast<std::size_t>(threads)); };
  server.set_keep_alive_max_count(100000);
  server.set_read_timeout(10, 0);
  server.set_tcp_nodelay(tcp_nodelay);
  server.Get(R"(/.*)", [&body](const httplib::Request&, httplib::Response& res) {
    res.set_content(body, "application/json");
  });

  const int bound = port == 0 ? server.bind_to_any_port(bind)
                              : (server.bind_to_port(bind, static_cast<int>(port)) ? static_cast<int>(port) : -1);
  if (bound < 0) {
    std::cerr << "anchordb_http_peer: cannot listen on " << bind << ":" << port << "\n";
    return 1;
  }
  std::thread signal_thread([&server, signals] {
    int received = 0;
    sigwait(&signals, &received);
    server.stop();
  });
  std::printf("anchordb_http_peer listening on http://%s:%d (bare cpp-httplib handler, %zu-byte JSON body, %ld threads, "
              "tcp_nodelay %s)\n",
              bind.c_str(), bound, body.size(), threads, tcp_nodelay ? "true" : "false");
  std::fflush(stdout);
  const bool ok = server.listen_after_bind();
  if (signal_thread.joinable()) {
    pthread_kill(signal_thread.native_handle(), SIGTERM);  // wakes sigwait if the server stopped for another reason
    signal_thread.join();
  }
  return ok ? 0 : 1;
}
