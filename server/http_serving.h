#pragma once
// Fair HTTP serving (SPEC §8 "no client is starved"): a worker pool that serves requests, not connections.
//
// One reactor thread (the caller of Run) owns the listening socket and every open connection. It watches idle
// keep-alive connections with epoll and reads request headers without blocking; a connection whose headers are
// complete is queued (FIFO) for the workers, one of which serves exactly that one request with cpp-httplib's own
// request processing (routing, body reading, Expect: 100-continue, payload limit, response writing) and hands the
// connection back. An idle keep-alive connection therefore holds no worker, and bytes pipelined behind a request stay
// in the connection's buffer (the connection is queued again at once when they hold a complete request).
//
// Limits (all in ServingLimits):
//  - max_connections open at once; one more closes the longest-idle keep-alive connection, or, if none is idle, is
//    answered at once with 503 + Retry-After + Connection: close;
//  - max_queued_requests waiting for a worker; one more is answered 503 + Retry-After + Connection: close;
//  - idle_timeout_s: an idle keep-alive connection is closed after this long;
//  - read_timeout_s: request headers must arrive within this long of their first byte, and every later read of the
//    body waits at most this long; write_timeout_s bounds each wait for the peer to take response bytes.
// Refused connections are answered and then drained briefly (so the client reads the 503 instead of a reset).
// Clients should retry an idempotent request on a new connection when a kept-alive one was closed under them.
#include <cstdint>
#include <memory>
#include <string>

namespace httplib {
class Server;
}

namespace anchordb::server {

struct ServingLimits {
  int worker_threads = 32;        // requests served at once
  int max_connections = 512;      // open client connections
  int max_queued_requests = 512;  // complete requests waiting for a worker
  int idle_timeout_s = 60;        // [s] an idle keep-alive connection is closed after this
  int read_timeout_s = 10;        // [s] see above
  int write_timeout_s = 5;        // [s] see above
  int retry_after_s = 1;          // [s] Retry-After of every 503 sent here
};

// Counters since start (gauges marked): what GET /metrics shows.
struct ServingCounters {
  std::int64_t connections_open = 0;       // gauge
  std::int64_t connections_idle = 0;       // gauge: open keep-alives waiting for a request (holding no worker)
  std::int64_t connections_accepted = 0;   // admitted connections
  std::int64_t connections_refused = 0;    // answered 503 at accept (every connection busy)
  std::int64_t idle_closed_timeout = 0;    // idle keep-alives closed after idle_timeout_s
  std::int64_t idle_closed_capacity = 0;   // idle keep-alives closed to admit a new connection
  std::int64_t requests_queued = 0;        // gauge: complete requests waiting for a worker
  std::int64_t requests_refused = 0;       // answered 503 because the queue was full
  std::int64_t requests_served = 0;        // served by a worker
  std::int64_t workers_busy = 0;           // gauge
};

class HttpServing {
 public:
  // Throws std::invalid_argument when a limit is not positive.
  explicit HttpServing(ServingLimits limits);
  ~HttpServing();
  HttpServing(const HttpServing&) = delete;
  HttpServing& operator=(const HttpServing&) = delete;

  // The route table: register handlers on it (api::HttpApi::Mount) before Run. Its own listen/stop are not used.
  httplib::Server& routes();

  // Binds and listens on host:port (port 0 = any free port); returns the bound port. Raises the soft limit of open
  // files when max_connections needs it. Throws std::runtime_error naming the cause.
  int Bind(const std::string& host, int port);

  // Serves until Stop: the calling thread is the reactor. On Stop, no connection is accepted any more, requests
  // already complete are answered (with Connection: close), then every connection is closed and the workers joined.
  void Run();

  // From any thread (a signal-handling thread, a test); idempotent. Also valid before Run (Run then returns at once).
  void Stop();

  ServingCounters counters() const;
  // The counters in Prometheus text format (anchordb_connections_open, ..._refused_total, anchordb_requests_queued...).
  std::string PrometheusText() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace anchordb::server
