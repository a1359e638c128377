#pragma once
// The one source of "now" (SPEC §1: integer nanoseconds since the Unix epoch). Services receive a Clock and never
// read the system time themselves, so tests run on a FakeClock they move by hand.
#include <atomic>
#include <chrono>
#include <cstdint>

namespace anchordb {

class Clock {
 public:
  virtual ~Clock() = default;
  virtual std::int64_t NowNs() const = 0;
};

class SystemClock final : public Clock {
 public:
  std::int64_t NowNs() const override {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
  }
  // The process-wide system clock (a default for code composed without an explicit clock).
  static const SystemClock& Instance() {
    static const SystemClock clock;
    return clock;
  }
};

// A clock that stands still until told otherwise (tests).
class FakeClock final : public Clock {
 public:
  explicit FakeClock(std::int64_t now_ns = 0) : now_ns_(now_ns) {}
  std::int64_t NowNs() const override { return now_ns_.load(); }
  void SetNs(std::int64_t now_ns) { now_ns_.store(now_ns); }
  void AdvanceNs(std::int64_t delta_ns) { now_ns_.fetch_add(delta_ns); }

 private:
  std::atomic<std::int64_t> now_ns_;
};

}  // namespace anchordb
