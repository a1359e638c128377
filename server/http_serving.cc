#include "server/http_serving.h"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <unordered_map>
#include <vector>

#include "api/http_api.h"
#include "server/http_connection.h"

namespace anchordb::server {
namespace {

using Clock = std::chrono::steady_clock;

// The reactor reads a request head up to this size before a worker takes over (cpp-httplib then reads the rest).
constexpr std::size_t kHeadBytes = 64 << 10;
// Refused connections still draining (so the client reads the 503, not a reset) and how long each may drain.
constexpr std::size_t kMaxLingering = 256;
constexpr auto kLingerTime = std::chrono::seconds(2);
// File descriptors beyond the connections: SQLite files, the epoll and event fds, logs.
constexpr rlim_t kSpareFiles = 128;

// cpp-httplib's request processing is protected: a subclass lets a worker run it on one request of a connection.
class RequestServer : public httplib::Server {
 public:
  bool ServeOne(httplib::Stream& stream, bool close_connection, bool& connection_closed) {
    return process_request(stream, close_connection, connection_closed, nullptr);
  }
  // cpp-httplib ends a streamed (chunked) response when its listening socket is invalid ("shutting down"). It never
  // listens here: the reactor's socket stands in while serving, and Stop invalidates it, so streams end on a stop.
  void SetServing(socket_t fd) { svr_sock_ = fd; }
};

struct Address {
  std::string ip;
  int port = 0;
};

Address AddressOf(const sockaddr_storage& a) {
  char text[INET6_ADDRSTRLEN] = {0};
  Address out;
  if (a.ss_family == AF_INET) {
    const auto& v4 = reinterpret_cast<const sockaddr_in&>(a);
    inet_ntop(AF_INET, &v4.sin_addr, text, sizeof(text));
    out.port = ntohs(v4.sin_port);
  } else if (a.ss_family == AF_INET6) {
    const auto& v6 = reinterpret_cast<const sockaddr_in6&>(a);
    inet_ntop(AF_INET6, &v6.sin6_addr, text, sizeof(text));
    out.port = ntohs(v6.sin6_port);
  }
  out.ip = text;
  return out;
}

std::string Refusal(const std::string& message, int retry_after_s) {
  const std::string body = api::ErrorBody(ErrorCode::kOverloaded, message, "");
  return "HTTP/1.1 503 Service Unavailable\r\nContent-Type: application/json\r\nContent-Length: " +
         std::to_string(body.size()) + "\r\nRetry-After: " + std::to_string(retry_after_s) +
         "\r\nConnection: close\r\n\r\n" + body;
}

// Tags of the two non-connection fds in epoll's user data.
char kListenTag, kWakeTag;

}  // namespace

struct HttpServing::Impl {
  explicit Impl(ServingLimits l)
      : limits(l),
        refusal_busy(Refusal("every connection is busy (" + std::to_string(l.max_connections) +
                                 " open); retry after " + std::to_string(l.retry_after_s) + " s",
                             l.retry_after_s)),
        refusal_queue(Refusal("too many requests waiting (" + std::to_string(l.max_queued_requests) +
                                  "); retry after " + std::to_string(l.retry_after_s) + " s",
                              l.retry_after_s)) {}

  // ---- reactor (the thread in Run) ----
  void Loop();
  void Accept();
  void OnReadable(Connection* c);
  void Arm(Connection* c) const;
  void Dispatch(Connection* c);
  void Linger(Connection* c, const std::string& response);
  void Close(Connection* c);
  void MakeIdle(Connection* c);
  void LeaveIdle(Connection* c);
  void TakeHandbacks();
  void Sweep(Clock::time_point now);
  void Wake() const {
    const std::uint64_t one = 1;
    [[maybe_unused]] const ssize_t n = ::write(wake_fd, &one, sizeof(one));
  }

  // ---- workers ----
  void Work();
  void Serve(Connection* c);
  void HandBack(Connection* c, bool close);

  ServingLimits limits;
  const std::string refusal_busy, refusal_queue;
  RequestServer routes;
  int listen_fd = -1, epoll_fd = -1, wake_fd = -1;
  std::atomic<bool> stopping{false};
  bool listen_paused = false;
  Clock::time_point listen_paused_until{};

  std::unordered_map<Connection*, std::unique_ptr<Connection>> connections;  // reactor only
  std::list<Connection*> idle;  // reactor only; front = idle longest
  std::vector<Connection*> closed;  // reactor only; freed at the end of each turn
  std::size_t lingering = 0;

  std::mutex queue_mutex;
  std::condition_variable queue_changed;
  std::deque<Connection*> queue;  // complete requests, FIFO
  bool workers_stop = false;
  std::vector<std::thread> workers;

  struct Handback {
    Connection* connection;
    bool close;
    Clock::time_point at;
  };
  std::mutex handback_mutex;
  std::vector<Handback> handbacks;

  struct {
    std::atomic<std::int64_t> open{0}, idle{0}, accepted{0}, refused{0}, idle_timeout{0}, idle_capacity{0}, queued{0},
        requests_refused{0}, served{0}, busy{0};
  } stats;
};

void HttpServing::Impl::Arm(Connection* c) const {
  epoll_event e{};
  e.events = EPOLLIN | EPOLLONESHOT | EPOLLRDHUP;
  e.data.ptr = c;
  epoll_ctl(epoll_fd, EPOLL_CTL_MOD, c->fd, &e);
}

void HttpServing::Impl::MakeIdle(Connection* c) {
  if (c->idle) return;
  c->idle = true;
  c->idle_position = idle.insert(idle.end(), c);
  ++stats.idle;
}

void HttpServing::Impl::LeaveIdle(Connection* c) {
  if (!c->idle) return;
  idle.erase(c->idle_position);
  c->idle = false;
  --stats.idle;
}

void HttpServing::Impl::Close(Connection* c) {
  if (c->state == Connection::State::kClosed) return;
  LeaveIdle(c);
  if (c->state == Connection::State::kLingering) --lingering;
  else --stats.open;
  c->state = Connection::State::kClosed;
  ::close(c->fd);  // also removes it from epoll; the object lives until the end of the turn (events may name it)
  c->fd = -1;
  closed.push_back(c);
}

void HttpServing::Impl::Linger(Connection* c, const std::string& response) {
  LeaveIdle(c);
  SendWithoutWaiting(c->fd, response);
  ::shutdown(c->fd, SHUT_WR);
  if (c->state != Connection::State::kLingering) --stats.open;
  c->state = Connection::State::kLingering;
  c->since = Clock::now();
  ++lingering;
  if (lingering > kMaxLingering) return Close(c);
  Arm(c);
}

void HttpServing::Impl::Accept() {
  for (;;) {
    sockaddr_storage peer{};
    socklen_t peer_size = sizeof(peer);
    const int fd = ::accept4(listen_fd, reinterpret_cast<sockaddr*>(&peer), &peer_size, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) {
      if (errno == EINTR || errno == ECONNABORTED) continue;
      if (errno == EMFILE || errno == ENFILE || errno == ENOBUFS || errno == ENOMEM) {
        // Out of descriptors: stop watching the listening socket for a moment instead of spinning on it.
        epoll_event e{};
        e.data.ptr = &kListenTag;
        epoll_ctl(epoll_fd, EPOLL_CTL_MOD, listen_fd, &e);
        listen_paused = true;
        listen_paused_until = Clock::now() + std::chrono::milliseconds(100);
      }
      return;  // EAGAIN: nothing more to accept
    }
    const int one = 1;
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
    auto owned = std::make_unique<Connection>(fd);
    Connection* c = owned.get();
    const Address remote = AddressOf(peer);
    c->remote_ip = remote.ip, c->remote_port = remote.port;
    sockaddr_storage local{};
    socklen_t local_size = sizeof(local);
    if (getsockname(fd, reinterpret_cast<sockaddr*>(&local), &local_size) == 0) {
      const Address l = AddressOf(local);
      c->local_ip = l.ip, c->local_port = l.port;
    }
    epoll_event e{};
    e.events = EPOLLIN | EPOLLONESHOT | EPOLLRDHUP;
    e.data.ptr = c;
    if (epoll_ctl(epoll_fd, EPOLL_CTL_ADD, fd, &e) != 0) continue;  // `owned` closes it
    connections.emplace(c, std::move(owned));
    ++stats.open;
    if (stats.open > limits.max_connections) {
      if (!idle.empty()) {
        Close(idle.front());  // the longest-idle keep-alive connection makes room
        ++stats.idle_capacity;
      } else {
        ++stats.refused;
        Linger(c, refusal_busy);
        continue;
      }
    }
    ++stats.accepted;
    c->since = Clock::now();
    MakeIdle(c);
  }
}

void HttpServing::Impl::OnReadable(Connection* c) {
  if (c->state == Connection::State::kClosed) return;  // closed earlier in this turn (evicted for a new one)
  if (c->state == Connection::State::kQueued) TakeHandbacks();  // its worker handed it back and armed it already
  const bool open = c->ReadAvailable(kHeadBytes);
  if (c->state == Connection::State::kLingering) {
    c->Consume(c->buffered());  // drained and dropped
    return open ? Arm(c) : Close(c);
  }
  if (c->failed || (!open && !c->HasRequestHead())) return Close(c);
  if (c->HasRequestHead() || c->buffered() >= kHeadBytes) return Dispatch(c);
  if (c->buffered() > 0 && c->idle) {  // the first bytes of a request: its head must be complete in read_timeout_s
    LeaveIdle(c);
    c->since = Clock::now();
  }
  Arm(c);
}

void HttpServing::Impl::Dispatch(Connection* c) {
  LeaveIdle(c);
  {
    std::lock_guard<std::mutex> lock(queue_mutex);
    if (queue.size() < static_cast<std::size_t>(limits.max_queued_requests)) {
      c->state = Connection::State::kQueued;
      queue.push_back(c);
      ++stats.queued;
      queue_changed.notify_one();
      return;
    }
  }
  ++stats.requests_refused;
  Linger(c, refusal_queue);
}

void HttpServing::Impl::TakeHandbacks() {
  std::vector<Handback> taken;
  {
    std::lock_guard<std::mutex> lock(handback_mutex);
    taken.swap(handbacks);
  }
  for (const Handback& h : taken) {
    if (h.close) {
      Close(h.connection);
      continue;
    }
    Connection* c = h.connection;  // its worker armed it already
    c->state = Connection::State::kReading;
    c->since = h.at;
    if (c->buffered() == 0) MakeIdle(c);
  }
}

void HttpServing::Impl::Sweep(Clock::time_point now) {
  const auto idle_limit = std::chrono::seconds(limits.idle_timeout_s);
  while (!idle.empty() && now - idle.front()->since >= idle_limit) {
    Close(idle.front());
    ++stats.idle_timeout;
  }
  const auto read_limit = std::chrono::seconds(limits.read_timeout_s);
  std::vector<Connection*> expired;
  for (const auto& [c, owned] : connections) {
    const bool partial = c->state == Connection::State::kReading && !c->idle && now - c->since >= read_limit;
    const bool drained = c->state == Connection::State::kLingering && now - c->since >= kLingerTime;
    if (partial || drained) expired.push_back(c);
  }
  for (Connection* c : expired) Close(c);
  if (listen_paused && now >= listen_paused_until) {
    epoll_event e{};
    e.events = EPOLLIN;
    e.data.ptr = &kListenTag;
    epoll_ctl(epoll_fd, EPOLL_CTL_MOD, listen_fd, &e);
    listen_paused = false;
  }
}

void HttpServing::Impl::Loop() {
  std::vector<epoll_event> events(256);
  Clock::time_point last_sweep = Clock::now();
  while (!stopping) {
    const int ready = epoll_wait(epoll_fd, events.data(), static_cast<int>(events.size()), 250);
    if (ready < 0 && errno != EINTR) throw std::runtime_error(std::string("epoll_wait: ") + std::strerror(errno));
    for (int i = 0; i < ready; ++i) {
      void* tag = events[i].data.ptr;
      if (tag == &kListenTag) {
        Accept();
      } else if (tag == &kWakeTag) {
        std::uint64_t count = 0;
        [[maybe_unused]] const ssize_t r = ::read(wake_fd, &count, sizeof(count));
      } else {
        OnReadable(static_cast<Connection*>(tag));
      }
    }
    TakeHandbacks();
    const auto now = Clock::now();
    if (now - last_sweep >= std::chrono::milliseconds(250)) {
      Sweep(now);
      last_sweep = now;
    }
    for (Connection* c : closed) connections.erase(c);
    closed.clear();
  }
}

void HttpServing::Impl::Work() {
  for (;;) {
    Connection* c = nullptr;
    {
      std::unique_lock<std::mutex> lock(queue_mutex);
      queue_changed.wait(lock, [this] { return !queue.empty() || workers_stop; });
      if (queue.empty()) return;  // stopping, and every complete request answered
      c = queue.front();
      queue.pop_front();
      --stats.queued;
    }
    Serve(c);
  }
}

void HttpServing::Impl::Serve(Connection* c) {
  ++stats.busy;
  bool close = true;
  try {
    ConnectionStream stream(*c, std::chrono::seconds(limits.read_timeout_s), std::chrono::seconds(limits.write_timeout_s));
    bool connection_closed = false;
    const bool ok = routes.ServeOne(stream, stopping.load(), connection_closed);
    const bool flushed = stream.Flush();
    close = !ok || !flushed || connection_closed || stopping || c->failed || (c->peer_closed && !c->HasRequestHead());
  } catch (const std::exception&) {
    close = true;  // out of memory in the stream itself; the handlers have their own catch-all
  }
  ++stats.served;
  --stats.busy;
  if (!close && c->HasRequestHead()) {  // pipelined: the next request goes to the back of the queue at once
    std::lock_guard<std::mutex> lock(queue_mutex);
    queue.push_back(c);
    ++stats.queued;
    queue_changed.notify_one();
    return;
  }
  HandBack(c, close);
}

void HttpServing::Impl::HandBack(Connection* c, bool close) {
  // A kept connection is watched again at once, by its worker: no wake-up of the reactor per request. The reactor
  // takes the hand-back before the connection's next event (OnReadable) or at its next turn (<= 250 ms), which is
  // all its idle bookkeeping needs. Arming under the lock: the reactor cannot take (and close) the connection before
  // it is armed, and an event after arming finds the hand-back there. A closed connection wakes the reactor, so that
  // its descriptor goes at once. The worker does not touch `c` after the unlock.
  {
    std::lock_guard<std::mutex> lock(handback_mutex);
    if (!close) Arm(c);
    handbacks.push_back({c, close, Clock::now()});
  }
  if (close) Wake();
}

HttpServing::HttpServing(ServingLimits limits) {
  if (limits.worker_threads < 1 || limits.max_connections < 1 || limits.max_queued_requests < 1 ||
      limits.idle_timeout_s < 1 || limits.read_timeout_s < 1 || limits.write_timeout_s < 1 || limits.retry_after_s < 0) {
    throw std::invalid_argument("serving limits must be positive");
  }
  impl_ = std::make_unique<Impl>(limits);
  impl_->epoll_fd = epoll_create1(EPOLL_CLOEXEC);
  impl_->wake_fd = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (impl_->epoll_fd < 0 || impl_->wake_fd < 0) {
    throw std::runtime_error(std::string("epoll/eventfd: ") + std::strerror(errno));
  }
  epoll_event e{};
  e.events = EPOLLIN;
  e.data.ptr = &kWakeTag;
  epoll_ctl(impl_->epoll_fd, EPOLL_CTL_ADD, impl_->wake_fd, &e);
  impl_->routes.set_keep_alive_timeout(limits.idle_timeout_s);  // what the Keep-Alive response header announces
  impl_->routes.set_keep_alive_max_count(100000);
}

HttpServing::~HttpServing() {
  for (int fd : {impl_->listen_fd, impl_->epoll_fd, impl_->wake_fd}) {
    if (fd >= 0) ::close(fd);
  }
}

httplib::Server& HttpServing::routes() { return impl_->routes; }

int HttpServing::Bind(const std::string& host, int port) {
  Impl& m = *impl_;
  rlimit files{};
  const rlim_t wanted = static_cast<rlim_t>(m.limits.max_connections) + kMaxLingering + kSpareFiles;
  if (getrlimit(RLIMIT_NOFILE, &files) == 0 && files.rlim_cur < wanted) {
    files.rlim_cur = std::min(wanted, files.rlim_max);
    setrlimit(RLIMIT_NOFILE, &files);
    if (files.rlim_cur < wanted) {
      throw std::runtime_error("max_connections " + std::to_string(m.limits.max_connections) + " needs " +
                               std::to_string(wanted) + " open files; the hard limit (ulimit -Hn) is " +
                               std::to_string(files.rlim_max));
    }
  }
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
  addrinfo* found = nullptr;
  if (const int r = getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &found); r != 0) {
    throw std::runtime_error("cannot resolve " + host + ": " + gai_strerror(r));
  }
  std::string error = "no address";
  for (addrinfo* a = found; a && m.listen_fd < 0; a = a->ai_next) {
    const int fd = ::socket(a->ai_family, a->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, a->ai_protocol);
    if (fd < 0) continue;
    const int one = 1;
    setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
    if (::bind(fd, a->ai_addr, a->ai_addrlen) == 0 && ::listen(fd, SOMAXCONN) == 0) {
      m.listen_fd = fd;
    } else {
      error = std::strerror(errno);
      ::close(fd);
    }
  }
  freeaddrinfo(found);
  if (m.listen_fd < 0) throw std::runtime_error("cannot listen on " + host + ":" + std::to_string(port) + ": " + error);
  sockaddr_storage bound{};
  socklen_t size = sizeof(bound);
  getsockname(m.listen_fd, reinterpret_cast<sockaddr*>(&bound), &size);
  return AddressOf(bound).port;
}

void HttpServing::Run() {
  Impl& m = *impl_;
  if (m.listen_fd < 0) throw std::logic_error("HttpServing::Run before Bind");
  epoll_event e{};
  e.events = EPOLLIN;
  e.data.ptr = &kListenTag;
  if (epoll_ctl(m.epoll_fd, EPOLL_CTL_ADD, m.listen_fd, &e) != 0) {
    throw std::runtime_error(std::string("epoll_ctl: ") + std::strerror(errno));
  }
  if (!m.stopping) m.routes.SetServing(m.listen_fd);
  for (int i = 0; i < m.limits.worker_threads; ++i) m.workers.emplace_back([&m] { m.Work(); });
  std::exception_ptr failure;
  try {
    m.Loop();
  } catch (...) {
    failure = std::current_exception();
    m.stopping = true;
  }
  // Stop: accept nothing more; the workers answer the complete requests already queued (Connection: close).
  m.routes.SetServing(INVALID_SOCKET);
  ::close(m.listen_fd);
  m.listen_fd = -1;
  {
    std::lock_guard<std::mutex> lock(m.queue_mutex);
    m.workers_stop = true;
  }
  m.queue_changed.notify_all();
  for (auto& w : m.workers) w.join();
  m.workers.clear();
  m.TakeHandbacks();
  m.idle.clear();
  m.closed.clear();
  m.connections.clear();
  m.stats.open = 0;
  m.stats.idle = 0;
  m.lingering = 0;
  if (failure) std::rethrow_exception(failure);
}

void HttpServing::Stop() {
  impl_->stopping = true;
  impl_->routes.SetServing(INVALID_SOCKET);
  impl_->Wake();
}

ServingCounters HttpServing::counters() const {
  const auto& stats = impl_->stats;
  ServingCounters c;
  c.connections_open = stats.open, c.connections_idle = stats.idle, c.connections_accepted = stats.accepted, c.connections_refused = stats.refused;
  c.idle_closed_timeout = stats.idle_timeout, c.idle_closed_capacity = stats.idle_capacity;
  c.requests_queued = stats.queued, c.requests_refused = stats.requests_refused, c.requests_served = stats.served;
  c.workers_busy = stats.busy;
  return c;
}

std::string HttpServing::PrometheusText() const {
  const ServingCounters c = counters();
  std::string out;
  const auto add = [&out](const char* name, const char* type, const char* help, const std::string& samples) {
    out += std::string("# HELP ") + name + " " + help + "\n# TYPE " + name + " " + type + "\n" + samples;
  };
  const auto one = [](const char* name, std::int64_t v) { return std::string(name) + " " + std::to_string(v) + "\n"; };
  add("anchordb_connections_open", "gauge", "Open client connections.", one("anchordb_connections_open", c.connections_open));
  add("anchordb_connections_idle", "gauge", "Open keep-alive connections waiting for a request (they hold no worker).",
      one("anchordb_connections_idle", c.connections_idle));
  add("anchordb_connections_accepted_total", "counter", "Client connections admitted.",
      one("anchordb_connections_accepted_total", c.connections_accepted));
  add("anchordb_connections_refused_total", "counter",
      "Connections answered 503 + Retry-After at once because max_connections were open and none idle.",
      one("anchordb_connections_refused_total", c.connections_refused));
  add("anchordb_connections_idle_closed_total", "counter", "Idle keep-alive connections closed, by reason.",
      "anchordb_connections_idle_closed_total{reason=\"timeout\"} " + std::to_string(c.idle_closed_timeout) +
          "\nanchordb_connections_idle_closed_total{reason=\"capacity\"} " + std::to_string(c.idle_closed_capacity) + "\n");
  add("anchordb_requests_queued", "gauge", "Complete requests waiting for a worker.",
      one("anchordb_requests_queued", c.requests_queued));
  add("anchordb_requests_refused_total", "counter", "Requests answered 503 + Retry-After because the queue was full.",
      one("anchordb_requests_refused_total", c.requests_refused));
  add("anchordb_requests_served_total", "counter", "Requests served by a worker.",
      one("anchordb_requests_served_total", c.requests_served));
  add("anchordb_workers_busy", "gauge", "Workers serving a request.", one("anchordb_workers_busy", c.workers_busy));
  return out;
}

}  // namespace anchordb::server
