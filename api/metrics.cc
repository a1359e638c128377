#include "api/metrics.h"

#include <sstream>

namespace anchordb::api {
namespace {
std::string Escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out;
}
}  // namespace

void Metrics::Record(const std::string& route, int status, double seconds) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++requests_[{route, status}];
  Histogram& h = latency_[route];
  for (std::size_t i = 0; i < kBucketsSeconds.size(); ++i) {
    if (seconds <= kBucketsSeconds[i]) ++h.buckets[i];
  }
  ++h.count;
  h.sum_seconds += seconds;
}

void Metrics::RecordRefusedWrite() {
  std::lock_guard<std::mutex> lock(mutex_);
  ++writes_refused_;
}

std::string Metrics::Prometheus() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::ostringstream out;
  out << "# HELP anchordb_http_requests_total HTTP requests by route and status.\n"
      << "# TYPE anchordb_http_requests_total counter\n";
  for (const auto& [key, n] : requests_) {
    out << "anchordb_http_requests_total{route=\"" << Escape(key.first) << "\",status=\"" << key.second << "\"} " << n << "\n";
  }
  out << "# HELP anchordb_http_request_duration_seconds Time from routing to response, by route.\n"
      << "# TYPE anchordb_http_request_duration_seconds histogram\n";
  for (const auto& [route, h] : latency_) {
    const std::string r = Escape(route);
    for (std::size_t i = 0; i < kBucketsSeconds.size(); ++i) {
      out << "anchordb_http_request_duration_seconds_bucket{route=\"" << r << "\",le=\"" << kBucketsSeconds[i] << "\"} "
          << h.buckets[i] << "\n";
    }
    out << "anchordb_http_request_duration_seconds_bucket{route=\"" << r << "\",le=\"+Inf\"} " << h.count << "\n"
        << "anchordb_http_request_duration_seconds_sum{route=\"" << r << "\"} " << h.sum_seconds << "\n"
        << "anchordb_http_request_duration_seconds_count{route=\"" << r << "\"} " << h.count << "\n";
  }
  out << "# HELP anchordb_writes_refused_total Write requests refused by admission control (503 + Retry-After).\n"
      << "# TYPE anchordb_writes_refused_total counter\n"
      << "anchordb_writes_refused_total " << writes_refused_ << "\n";
  return out.str();
}

}  // namespace anchordb::api
