#pragma once
// Request counters and latency histograms per route, served as Prometheus text (GET /metrics).
#include <array>
#include <map>
#include <mutex>
#include <string>

namespace anchordb::api {

class Metrics {
 public:
  // `route` is the route's pattern ("GET /v1/maps/{map}"), so ids never explode the label set.
  void Record(const std::string& route, int status, double seconds);
  // A write refused by admission control (503 + Retry-After).
  void RecordRefusedWrite();
  std::string Prometheus() const;

 private:
  static constexpr std::array<double, 12> kBucketsSeconds = {0.0005, 0.001, 0.0025, 0.005, 0.01, 0.025,
                                                             0.05,   0.1,   0.25,   0.5,   1.0,  5.0};
  struct Histogram {
    std::array<std::uint64_t, kBucketsSeconds.size()> buckets{};
    std::uint64_t count = 0;
    double sum_seconds = 0.0;
  };
  mutable std::mutex mutex_;
  std::map<std::pair<std::string, int>, std::uint64_t> requests_;  // (route, status) -> count
  std::map<std::string, Histogram> latency_;
  std::uint64_t writes_refused_ = 0;
};

}  // namespace anchordb::api
