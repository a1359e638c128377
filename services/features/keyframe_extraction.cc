#include "services/features/keyframe_extraction.h"

#include <chrono>

namespace anchordb::services {

KeyframeExtraction::KeyframeExtraction(FeatureService& features, KeyframeListener* next, bool enabled)
    : features_(features), next_(next), enabled_(enabled) {
  if (enabled_) worker_ = std::thread([this] { Worker(); });
}

KeyframeExtraction::~KeyframeExtraction() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (worker_.joinable()) worker_.join();
}

void KeyframeExtraction::Enqueue(storage::Connection& c, const QueuedKeyframe& keyframe) {
  if (next_) next_->Enqueue(c, keyframe);
  if (!enabled_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  pending_.emplace_back(keyframe.map, keyframe.keyframe_id);
}

void KeyframeExtraction::Admit(const std::string& map) {
  if (next_) next_->Admit(map);
}

void KeyframeExtraction::Enqueued(const std::string& map) {
  if (next_) next_->Enqueued(map);
  if (!enabled_) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    // A keyframe whose transaction rolled back stays pending until its map's next commit; its extraction then finds
    // no keyframe and is counted as failed.
    for (auto it = pending_.begin(); it != pending_.end();) {
      if (it->first == map) {
        queue_.push_back(*it);
        it = pending_.erase(it);
      } else {
        ++it;
      }
    }
  }
  wake_.notify_all();
}

KeyframeAnalysisStatus KeyframeExtraction::Await(std::int64_t keyframe_id) {
  if (next_) return next_->Await(keyframe_id);
  KeyframeAnalysisStatus s;
  s.state = AnalysisState::kSkipped;
  s.keyframe_id = keyframe_id;
  return s;
}

bool KeyframeExtraction::WaitIdle(double timeout_s) {
  std::unique_lock<std::mutex> lock(mutex_);
  return idle_.wait_for(lock, std::chrono::duration<double>(timeout_s), [&] { return queue_.empty() && !running_; });
}

int KeyframeExtraction::extracted() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return extracted_;
}

int KeyframeExtraction::failed() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return failed_;
}

void KeyframeExtraction::Worker() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    wake_.wait(lock, [&] { return stop_ || !queue_.empty(); });
    if (stop_) return;
    const auto [map, keyframe] = queue_.front();
    queue_.pop_front();
    running_ = true;
    lock.unlock();
    bool ok = true;
    try {
      features_.ExtractKeyframe(map, keyframe, ExtractRequest{});
    } catch (const std::exception&) {
      ok = false;
    }
    lock.lock();
    running_ = false;
    (ok ? extracted_ : failed_) += 1;
    if (queue_.empty()) idle_.notify_all();
  }
}

}  // namespace anchordb::services
