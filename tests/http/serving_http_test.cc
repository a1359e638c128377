// Fair serving (server/http_serving.h, SPEC §8 "no client is starved") over real sockets on loopback against the
// anchordb binary: more keep-alive connections than workers are all answered, idle ones hold no worker, the
// connection beyond max_connections is answered 503 + Retry-After at once (or takes the place of an idle one),
// a full request queue answers 503 + Retry-After, pipelined requests are answered in order, SIGTERM with idle
// connections open stops cleanly. Raw sockets, so the test controls exactly what each connection sends; the only
// clock is a generous read timeout that turns "never answered" into a failure instead of a hang.
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "tests/support/server_process.h"
#include "tests/support/temp_dir.h"

namespace anchordb {
namespace serving_http_test {

constexpr int kNeverAnsweredMs = 30000;  // a response not here by then is a response that never comes

struct HttpAnswer {
  int status = 0;
  std::map<std::string, std::string> headers;  // lower-case names
  std::string body;
  std::string header(const std::string& name) const {
    const auto it = headers.find(name);
    return it == headers.end() ? std::string() : it->second;
  }
};

// One client connection speaking HTTP/1.1 by hand.
class RawConnection {
 public:
  explicit RawConnection(int port) : fd_(::socket(AF_INET, SOCK_STREAM, 0)) {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    connected_ = ::connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof(a)) == 0;
    const int one = 1;
    setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
  }
  ~RawConnection() { ::close(fd_); }
  RawConnection(const RawConnection&) = delete;
  RawConnection& operator=(const RawConnection&) = delete;

  bool connected() const { return connected_; }
  bool Send(const std::string& bytes) {
    std::size_t sent = 0;
    while (sent < bytes.size()) {
      const ssize_t n = ::send(fd_, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
      if (n <= 0) return false;
      sent += static_cast<std::size_t>(n);
    }
    return true;
  }
  // The next response, or nullopt when the server closed the connection or sent nothing in time.
  std::optional<HttpAnswer> Read() {
    std::size_t head_end;
    while ((head_end = buffer_.find("\r\n\r\n")) == std::string::npos) {
      if (!Fill()) return std::nullopt;
    }
    HttpAnswer answer;
    const std::string head = buffer_.substr(0, head_end);
    answer.status = std::atoi(head.c_str() + head.find(' ') + 1);
    for (std::size_t line = head.find("\r\n"); line != std::string::npos;) {
      const std::size_t next = head.find("\r\n", line + 2);
      const std::string text = head.substr(line + 2, next == std::string::npos ? std::string::npos : next - line - 2);
      const auto colon = text.find(':');
      if (colon != std::string::npos) {
        std::string name = text.substr(0, colon);
        for (char& ch : name) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
        answer.headers[name] = text.substr(text.find_first_not_of(' ', colon + 1));
      }
      line = next;
    }
    const std::size_t length = static_cast<std::size_t>(std::atol(answer.header("content-length").c_str()));
    while (buffer_.size() < head_end + 4 + length) {
      if (!Fill()) return std::nullopt;
    }
    answer.body = buffer_.substr(head_end + 4, length);
    buffer_.erase(0, head_end + 4 + length);
    return answer;
  }
  // Whether a response (or the close) has arrived within `timeout_ms`.
  bool HasData(int timeout_ms) {
    pollfd p{fd_, POLLIN, 0};
    return !buffer_.empty() || ::poll(&p, 1, timeout_ms) > 0;
  }
  // Whether the server closed the connection (EOF with nothing more sent) within the timeout.
  bool ClosedByServer() { return buffer_.empty() && !Fill(); }

 private:
  bool Fill() {
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, kNeverAnsweredMs) <= 0) return false;
    char chunk[16384];
    const ssize_t n = ::recv(fd_, chunk, sizeof(chunk), 0);
    if (n <= 0) return false;
    buffer_.append(chunk, static_cast<std::size_t>(n));
    return true;
  }

  int fd_;
  bool connected_ = false;
  std::string buffer_;
};

std::string Get(const std::string& path, const std::string& extra_headers = "") {
  return "GET " + path + " HTTP/1.1\r\nHost: test\r\n" + extra_headers + "\r\n";
}

// The value of a sample line "name value" (or "name{labels} value") in Prometheus text; -1 when absent.
long Sample(const std::string& metrics, const std::string& name) {
  const std::size_t at = metrics.find("\n" + name + " ");
  return at == std::string::npos ? -1 : std::atol(metrics.c_str() + at + name.size() + 2);
}

class ServingHttpTest : public ::testing::Test {
 protected:
  void Start(std::vector<std::string> args) {
    server_ = std::make_unique<testing::ServerProcess>(dir_.File("serving.sqlite"), std::move(args));
  }
  int port() const { return server_->port(); }
  // `n` keep-alive connections that each had one request answered and now wait, idle; fewer if one was not answered.
  std::vector<std::unique_ptr<RawConnection>> IdleConnections(int n) {
    std::vector<std::unique_ptr<RawConnection>> out;
    for (int i = 0; i < n; ++i) {
      auto c = std::make_unique<RawConnection>(port());
      if (!c->Send(Get("/v1/maps")) || !c->Read()) break;
      out.push_back(std::move(c));
    }
    return out;
  }

  testing::TempDir dir_;
  std::unique_ptr<testing::ServerProcess> server_;
};

void ExpectRefusal(const std::optional<HttpAnswer>& a) {
  ASSERT_TRUE(a) << "a refused connection must still be answered";
  EXPECT_EQ(a->status, 503);
  EXPECT_EQ(a->header("retry-after"), "1");
  EXPECT_EQ(a->header("connection"), "close");
  EXPECT_NE(a->body.find("\"code\":\"overloaded\""), std::string::npos) << a->body;
}

TEST_F(ServingHttpTest, TwoHundredKeepAliveConnectionsOnFourWorkersAreAllAnswered) {
  Start({"--threads=4"});
  std::vector<std::unique_ptr<RawConnection>> clients;
  for (int i = 0; i < 200; ++i) {
    clients.push_back(std::make_unique<RawConnection>(port()));
    ASSERT_TRUE(clients.back()->connected()) << i;
  }
  // Two rounds: every connection stays open (keep-alive) between its requests, so with one worker per connection
  // only the first four would ever be answered.
  for (int round = 0; round < 2; ++round) {
    for (auto& c : clients) ASSERT_TRUE(c->Send(Get("/v1/health")));
    for (std::size_t i = 0; i < clients.size(); ++i) {
      const auto a = clients[i]->Read();
      ASSERT_TRUE(a) << "connection " << i << " was never answered in round " << round;
      EXPECT_EQ(a->status, 200);
      EXPECT_EQ(a->header("connection"), "");  // kept alive
      EXPECT_FALSE(a->header("x-request-id").empty());
    }
  }
}

TEST_F(ServingHttpTest, IdleKeepAlivesBeyondTheWorkersDoNotBlockANewConnection) {
  Start({"--threads=2"});
  const auto idle = IdleConnections(20);
  ASSERT_EQ(idle.size(), 20u);
  RawConnection fresh(port());
  ASSERT_TRUE(fresh.Send(Get("/v1/health")));
  const auto a = fresh.Read();
  ASSERT_TRUE(a) << "20 idle keep-alive connections held the 2 workers";
  EXPECT_EQ(a->status, 200);
  for (auto& c : idle) {  // and every idle one is still served
    ASSERT_TRUE(c->Send(Get("/v1/health")));
    const auto again = c->Read();
    ASSERT_TRUE(again);
    EXPECT_EQ(again->status, 200);
  }
}

// A monitoring connection that is never idle: each round sends the rest of a pending request head, GET /metrics and
// the start of the next request head in one write, so it is in service or mid-head whenever a new connection comes.
class BusyMonitor {
 public:
  explicit BusyMonitor(int port) : c_(port) {}
  std::string Metrics() {
    const std::string metrics_request = Get("/metrics");
    EXPECT_TRUE(c_.Send((first_ ? "" : "Host: m\r\n\r\n") + metrics_request + "GET /v1/health HTTP/1.1\r\n"));
    if (!first_) {
      const auto health = c_.Read();
      EXPECT_TRUE(health && health->status == 200);
    }
    first_ = false;
    const auto metrics = c_.Read();
    EXPECT_TRUE(metrics && metrics->status == 200);
    return metrics ? "\n" + metrics->body : std::string();
  }
  // Polls /metrics until `name` has `value` (what the reactor does is asynchronous to the clients).
  std::string WaitFor(const std::string& name, long value) {
    for (int i = 0; i < 5000; ++i) {
      const std::string m = Metrics();
      if (Sample(m, name) == value) return m;
      usleep(2000);
    }
    ADD_FAILURE() << name << " never reached " << value;
    return {};
  }

 private:
  RawConnection c_;
  bool first_ = true;
};

TEST_F(ServingHttpTest, BeyondMaxConnectionsANewConnectionTakesAnIdleOnesPlaceOrIsAnswered503) {
  Start({"--max_connections=3"});
  RawConnection a(port()), b(port());
  ASSERT_TRUE(a.Send("GET /v1/health HTTP/1.1\r\nHost: a\r\n"));  // mid-head: open, not idle
  ASSERT_TRUE(b.Send("GET /v1/health HTTP/1.1\r\nHost: b\r\n"));
  BusyMonitor monitor(port());
  monitor.WaitFor("anchordb_connections_idle", 0);
  EXPECT_EQ(Sample(monitor.Metrics(), "anchordb_connections_open"), 3);

  RawConnection refused(port());  // none idle: answered at once, then closed
  ExpectRefusal(refused.Read());
  EXPECT_TRUE(refused.ClosedByServer());
  EXPECT_EQ(Sample(monitor.Metrics(), "anchordb_connections_refused_total"), 1);

  ASSERT_TRUE(a.Send("\r\n"));  // a's request completes; afterwards a is an idle keep-alive
  const auto answered = a.Read();
  ASSERT_TRUE(answered);
  EXPECT_EQ(answered->status, 200);
  monitor.WaitFor("anchordb_connections_idle", 1);
  RawConnection admitted(port());  // the longest-idle connection (a) is closed to make room
  ASSERT_TRUE(admitted.Send(Get("/v1/health")));
  const auto welcome = admitted.Read();
  ASSERT_TRUE(welcome);
  EXPECT_EQ(welcome->status, 200);
  EXPECT_TRUE(a.ClosedByServer());
  const std::string m = monitor.Metrics();
  EXPECT_NE(m.find("anchordb_connections_idle_closed_total{reason=\"capacity\"} 1"), std::string::npos) << m;
  ASSERT_TRUE(b.Send("\r\n"));  // b, mid-head all along, was neither refused nor closed
  const auto b_answer = b.Read();
  ASSERT_TRUE(b_answer);
  EXPECT_EQ(b_answer->status, 200);
}

TEST_F(ServingHttpTest, AFullRequestQueueAnswers503WithRetryAfterAtOnce) {
  Start({"--threads=1", "--max_queued_requests=1"});
  // The only worker is held by a write whose body has not all arrived (it waits for the rest up to the read timeout).
  RawConnection held(port());
  const std::string body = R"({"id":"held","name":"waits for its body"})";
  ASSERT_TRUE(held.Send("POST /v1/maps HTTP/1.1\r\nHost: t\r\nContent-Type: application/json\r\nContent-Length: " +
                        std::to_string(body.size()) + "\r\n\r\n" + body.substr(0, 10)));
  std::vector<std::unique_ptr<RawConnection>> others;
  for (int i = 0; i < 5; ++i) {
    others.push_back(std::make_unique<RawConnection>(port()));
    ASSERT_TRUE(others.back()->Send(Get("/v1/health")));
  }
  // While the worker is held, at most one of the five fits the queue (the held write itself is queued first, then in
  // service); every other one is answered 503 + Retry-After now, before the worker is free.
  std::vector<bool> answered(others.size(), false);
  int refused = 0;
  for (int polls = 0; refused < 4 && polls < kNeverAnsweredMs / 10; ++polls) {
    for (std::size_t i = 0; i < others.size(); ++i) {
      if (answered[i] || !others[i]->HasData(10)) continue;
      answered[i] = true;
      ExpectRefusal(others[i]->Read());
      ++refused;
    }
  }
  ASSERT_GE(refused, 4) << "connections beyond the queue were not refused while the worker was held";
  ASSERT_TRUE(held.Send(body.substr(10)));
  const auto created = held.Read();
  ASSERT_TRUE(created);
  EXPECT_EQ(created->status, 201);
  for (std::size_t i = 0; i < others.size(); ++i) {
    if (answered[i]) continue;
    // The one that was queued is served once the worker is free; or, when the worker took the held write only after
    // all five had come, this one was refused as well.
    const auto a = others[i]->Read();
    ASSERT_TRUE(a);
    if (a->status == 503) {
      ExpectRefusal(a);
    } else {
      EXPECT_EQ(a->status, 200);
    }
  }
}

TEST_F(ServingHttpTest, PipelinedRequestsOnOneConnectionAreAnsweredInOrder) {
  Start({"--threads=4"});
  RawConnection c(port());
  const std::string map = R"({"id":"piped","name":"pipelined"})";
  // One write: a read, a write with a body, a read of what the write made, an unknown route, a read; the write's
  // body is followed at once by the next request's head, which must not be lost.
  std::string bytes = Get("/v1/health", "X-Request-Id: p1\r\n") +
                      "POST /v1/maps HTTP/1.1\r\nHost: t\r\nX-Request-Id: p2\r\nContent-Type: application/json\r\n"
                      "Content-Length: " + std::to_string(map.size()) + "\r\n\r\n" + map +
                      Get("/v1/maps/piped", "X-Request-Id: p3\r\n") + Get("/v1/nothing", "X-Request-Id: p4\r\n") +
                      Get("/v1/maps", "X-Request-Id: p5\r\n");
  ASSERT_TRUE(c.Send(bytes));
  const std::vector<std::pair<std::string, int>> expected = {{"p1", 200}, {"p2", 201}, {"p3", 200}, {"p4", 404}, {"p5", 200}};
  for (const auto& [id, status] : expected) {
    const auto a = c.Read();
    ASSERT_TRUE(a) << id << " never answered";
    EXPECT_EQ(a->header("x-request-id"), id);
    EXPECT_EQ(a->status, status) << id << " " << a->body;
    if (id == "p3") {
      EXPECT_NE(a->body.find("\"pipelined\""), std::string::npos) << a->body;
    }
  }
  // A request split across writes at awkward places is answered as well.
  ASSERT_TRUE(c.Send("GET /v1/hea"));
  ASSERT_TRUE(c.Send("lth HTTP/1.1\r\nHost: t\r"));
  ASSERT_TRUE(c.Send("\n\r\n"));
  const auto split = c.Read();
  ASSERT_TRUE(split);
  EXPECT_EQ(split->status, 200);
}

TEST_F(ServingHttpTest, SigtermWithIdleKeepAlivesOpenStopsCleanly) {
  Start({"--threads=2"});
  const auto idle = IdleConnections(50);
  ASSERT_EQ(idle.size(), 50u);
  RawConnection mid_head(port());
  ASSERT_TRUE(mid_head.Send("GET /v1/health HTTP/1.1\r\n"));
  const int status = server_->Stop();  // waits for the process; a server held by its idle connections would hang here
  EXPECT_TRUE(WIFEXITED(status)) << status;
  EXPECT_EQ(WEXITSTATUS(status), 0);
  for (auto& c : idle) EXPECT_TRUE(c->ClosedByServer());
  EXPECT_TRUE(mid_head.ClosedByServer());
}

}  // namespace
}  // namespace anchordb
