#include "server/http_connection.h"

#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <algorithm>
#include <cstring>

namespace anchordb::server {
namespace {

constexpr std::size_t kReadChunkBytes = 16 << 10;
// Writes up to this size are gathered; a larger one is sent from the caller's buffer after what is gathered.
constexpr std::size_t kGatherBytes = 64 << 10;

}  // namespace

Connection::~Connection() {
  if (fd >= 0) ::close(fd);
}

void Connection::Consume(std::size_t n) {
  in_begin += n;
  if (in_begin == in_end) in_begin = in_end = 0;
}

bool Connection::HasRequestHead() const {
  const char* data = buffered_data();
  const std::size_t n = buffered();
  // cpp-httplib ends the headers at the first empty line (CRLF CRLF; a bare LF line is read as a header line).
  return n >= 4 && memmem(data, n, "\r\n\r\n", 4) != nullptr;
}

bool Connection::ReadAvailable(std::size_t limit_bytes) {
  while (buffered() < limit_bytes) {
    if (in_capacity - in_end < kReadChunkBytes) {  // make room: move the buffered bytes to the front, or grow
      const std::size_t kept = buffered();
      if (in_capacity - kept >= kReadChunkBytes) {
        std::memmove(in.get(), in.get() + in_begin, kept);
      } else {
        const std::size_t capacity = std::max(2 * in_capacity, kept + kReadChunkBytes);
        auto bigger = std::make_unique_for_overwrite<char[]>(capacity);
        if (kept > 0) std::memcpy(bigger.get(), in.get() + in_begin, kept);
        in = std::move(bigger);
        in_capacity = capacity;
      }
      in_begin = 0;
      in_end = kept;
    }
    const std::size_t room = in_capacity - in_end;
    const ssize_t n = ::recv(fd, in.get() + in_end, room, 0);
    if (n > 0) {
      in_end += static_cast<std::size_t>(n);
      if (static_cast<std::size_t>(n) < room) return true;  // drained for now; epoll or poll says when more came
      continue;
    }
    if (n == 0) {
      peer_closed = true;
      return false;
    }
    if (errno == EINTR) continue;
    if (errno == EAGAIN || errno == EWOULDBLOCK) return true;
    failed = true;
    return false;
  }
  return true;
}

bool ConnectionStream::WaitFor(short events, std::chrono::milliseconds timeout) const {
  pollfd p{c_.fd, events, 0};
  for (;;) {
    const int r = ::poll(&p, 1, static_cast<int>(timeout.count()));
    if (r > 0) return true;
    if (r == 0) return false;
    if (errno != EINTR) return false;
  }
}

bool ConnectionStream::is_readable() const { return c_.buffered() > 0 || WaitFor(POLLIN, read_timeout_); }

// Also sends what is gathered, and says false once the peer hung up: a streamed response (api::Response::stream) asks
// after each piece and between pieces, so a Server-Sent Event leaves at once instead of waiting for the gather buffer
// to fill, and a stream whose client went away frees its worker at its next poll instead of at its next write.
bool ConnectionStream::is_writable() const {
  if (!const_cast<ConnectionStream*>(this)->Flush()) return false;
  pollfd p{c_.fd, POLLRDHUP, 0};
  return !(::poll(&p, 1, 0) > 0 && (p.revents & (POLLRDHUP | POLLHUP | POLLERR)));
}

ssize_t ConnectionStream::read(char* ptr, std::size_t size) {
  if (c_.buffered() == 0) {
    if (!Flush()) return -1;
    if (c_.peer_closed) return 0;
    if (c_.failed) return -1;
    for (;;) {
      if (!WaitFor(POLLIN, read_timeout_)) return -1;
      if (!c_.ReadAvailable(kReadChunkBytes) && c_.buffered() == 0) return c_.peer_closed ? 0 : -1;
      if (c_.buffered() > 0) break;
    }
  }
  const std::size_t n = std::min(size, c_.buffered());
  std::memcpy(ptr, c_.buffered_data(), n);
  c_.Consume(n);
  return static_cast<ssize_t>(n);
}

ssize_t ConnectionStream::write(const char* ptr, std::size_t size) {
  if (c_.failed) return -1;
  if (out_.size() + size > kGatherBytes) {
    if (!Flush()) return -1;
    if (size > kGatherBytes) return SendAll(ptr, size) ? static_cast<ssize_t>(size) : -1;
  }
  out_.append(ptr, size);
  return static_cast<ssize_t>(size);
}

void ConnectionStream::get_remote_ip_and_port(std::string& ip, int& port) const {
  ip = c_.remote_ip;
  port = c_.remote_port;
}

void ConnectionStream::get_local_ip_and_port(std::string& ip, int& port) const {
  ip = c_.local_ip;
  port = c_.local_port;
}

bool ConnectionStream::Flush() {
  if (out_.empty()) return !c_.failed;
  const bool ok = SendAll(out_.data(), out_.size());
  out_.clear();
  return ok;
}

bool ConnectionStream::SendAll(const char* data, std::size_t size) {
  while (size > 0 && !c_.failed) {
    const ssize_t n = ::send(c_.fd, data, size, MSG_NOSIGNAL);
    if (n > 0) {
      data += n;
      size -= static_cast<std::size_t>(n);
    } else if (n < 0 && errno == EINTR) {
      continue;
    } else if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      if (!WaitFor(POLLOUT, write_timeout_)) c_.failed = true;
    } else {
      c_.failed = true;
    }
  }
  return !c_.failed;
}

void SendWithoutWaiting(int fd, const std::string& bytes) {
  std::size_t sent = 0;
  while (sent < bytes.size()) {
    const ssize_t n = ::send(fd, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n > 0) sent += static_cast<std::size_t>(n);
    else if (!(n < 0 && errno == EINTR)) return;
  }
}

}  // namespace anchordb::server
