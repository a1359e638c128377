#include "services/octomap/octomap_keyframe_feed.h"

#include <algorithm>
#include <cstdio>

namespace anchordb::services {

OctomapKeyframeFeed::OctomapKeyframeFeed(OctomapService& octomap, KeyframeListener& next)
    : octomap_(octomap), next_(next) {}

OctomapKeyframeFeed::~OctomapKeyframeFeed() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  if (worker_.joinable()) worker_.join();
  try {
    octomap_.CommitPending();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "octomap: storing the pending trees at the stop failed: %s\n", e.what());
  }
}

void OctomapKeyframeFeed::FollowAtStart(const std::vector<std::string>& maps) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stopping_ || maps.empty()) return;
    for (const std::string& map : maps) pending_.try_emplace(map, 0);  // 0: no analysis to wait for
    if (!worker_.joinable()) worker_ = std::thread([this] { Worker(); });
  }
  changed_.notify_all();
}

void OctomapKeyframeFeed::Enqueue(storage::Connection& c, const QueuedKeyframe& keyframe) {
  next_.Enqueue(c, keyframe);
  std::lock_guard<std::mutex> lock(mutex_);
  staged_[keyframe.map] = keyframe.keyframe_id;
}

void OctomapKeyframeFeed::Admit(const std::string& map) { next_.Admit(map); }

void OctomapKeyframeFeed::Enqueued(const std::string& map) {
  next_.Enqueued(map);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stopping_) return;
    const auto staged = staged_.find(map);
    std::int64_t& newest = pending_[map];
    if (staged != staged_.end()) {
      newest = std::max(newest, staged->second);
      staged_.erase(staged);
    }
    if (!worker_.joinable()) worker_ = std::thread([this] { Worker(); });
  }
  changed_.notify_all();
}

KeyframeAnalysisStatus OctomapKeyframeFeed::Await(std::int64_t keyframe_id) { return next_.Await(keyframe_id); }

void OctomapKeyframeFeed::Drain() {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [this] { return (pending_.empty() && !busy_) || stopping_; });
}

FollowReport OctomapKeyframeFeed::totals() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return totals_;
}

std::size_t OctomapKeyframeFeed::failures() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return failures_;
}

void OctomapKeyframeFeed::Worker() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    changed_.wait(lock, [this] { return !pending_.empty() || stopping_; });
    if (stopping_) return;
    const auto [map, keyframe_id] = *pending_.begin();
    pending_.erase(pending_.begin());
    busy_ = true;
    lock.unlock();
    FollowReport report;
    bool failed = false;
    try {
      // Removal events come from the keyframe's change analysis: wait for it (bounded by the queue's setting).
      if (octomap_.settings().from_keyframes || octomap_.HasTree(map)) {
        if (keyframe_id > 0) next_.Await(keyframe_id);
        report = octomap_.Follow(map);
      }
    } catch (const std::exception& e) {
      failed = true;
      std::fprintf(stderr, "octomap: following map '%s' failed: %s\n", map.c_str(), e.what());
    }
    lock.lock();
    busy_ = false;
    failures_ += failed;
    totals_.keyframes_integrated += report.keyframes_integrated;
    totals_.removal_events += report.removal_events;
    totals_.voxels_cleared += report.voxels_cleared;
    changed_.notify_all();
  }
}

}  // namespace anchordb::services
