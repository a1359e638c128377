#pragma once
// Internal to server/http_serving.cc: one client connection (its socket, addresses and read buffer) and the
// httplib::Stream a worker serves one request through. Sockets are non-blocking; the stream waits with poll().
#include <chrono>
#include <cstddef>
#include <list>
#include <memory>
#include <string>

#include "api/router.h"  // Eigen before httplib (see api/router.h)

namespace anchordb::server {

struct Connection {
  // kReading: the reactor's (idle, or reading a request head); kQueued: the workers' (waiting or being served);
  // kLingering: refused, answered, draining until closed; kClosed: closed, freed at the end of the reactor's turn.
  enum class State { kReading, kQueued, kLingering, kClosed };

  explicit Connection(int socket_fd) : fd(socket_fd) {}
  ~Connection();  // closes the socket
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;

  // Bytes received and not yet consumed by a request.
  std::size_t buffered() const { return in_end - in_begin; }
  const char* buffered_data() const { return in.get() + in_begin; }
  void Consume(std::size_t n);
  // Whether the buffer holds a whole request head (request line and headers up to the empty line).
  bool HasRequestHead() const;
  // Reads what the socket has now, without blocking, until `limit_bytes` are buffered. Returns false when the peer
  // closed (sets peer_closed) or the socket failed (sets failed).
  bool ReadAvailable(std::size_t limit_bytes);

  int fd = -1;
  std::string remote_ip, local_ip;
  int remote_port = 0, local_port = 0;
  std::unique_ptr<char[]> in;  // [in_begin, in_end) is buffered
  std::size_t in_capacity = 0, in_begin = 0, in_end = 0;
  bool peer_closed = false;
  bool failed = false;
  State state = State::kReading;
  // Reactor bookkeeping: since when idle (empty buffer) or since the first byte of a partial request head.
  std::chrono::steady_clock::time_point since{};
  bool idle = false;
  std::list<Connection*>::iterator idle_position{};
};

// One request's view of a connection: reads come from the connection's buffer first (pipelined bytes survive the
// request), then from the socket, each wait bounded by the read timeout; writes are gathered and sent in few
// syscalls (flushed before any wait for input, so "100 Continue" reaches the client before its body is awaited).
class ConnectionStream final : public httplib::Stream {
 public:
  ConnectionStream(Connection& connection, std::chrono::milliseconds read_timeout,
                   std::chrono::milliseconds write_timeout)
      : c_(connection), read_timeout_(read_timeout), write_timeout_(write_timeout) {}

  bool is_readable() const override;
  bool is_writable() const override;  // flushes (see the .cc)
  ssize_t read(char* ptr, std::size_t size) override;
  ssize_t write(const char* ptr, std::size_t size) override;
  void get_remote_ip_and_port(std::string& ip, int& port) const override;
  void get_local_ip_and_port(std::string& ip, int& port) const override;
  socket_t socket() const override { return c_.fd; }

  // Sends what is gathered; false (and the connection marked failed) when the peer does not take it in time.
  bool Flush();

 private:
  bool WaitFor(short events, std::chrono::milliseconds timeout) const;
  bool SendAll(const char* data, std::size_t size);

  Connection& c_;
  std::chrono::milliseconds read_timeout_;
  std::chrono::milliseconds write_timeout_;
  std::string out_;
};

// Sends `bytes` without waiting (what the socket buffer takes); for the canned refusals of the reactor.
void SendWithoutWaiting(int fd, const std::string& bytes);

}  // namespace anchordb::server
