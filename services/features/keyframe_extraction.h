#pragma once
// Feature extraction from every new keyframe (setting features_extract_every_keyframe): a KeyframeListener placed
// in front of the analysis queue. It forwards every call to the next listener and, after the keyframe's write
// committed, extracts fpfh, shot and spd on its own worker thread (outside the write lock; PCL time is not spent on
// the frame path). Not durable: keyframes queued when the server stops are not extracted later (POST
// .../keyframes/{kf}:extract does it on request).
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "services/features/feature_service.h"
#include "services/scene/keyframe_listener.h"

namespace anchordb::services {

class KeyframeExtraction final : public KeyframeListener {
 public:
  // `next` (may be null) receives every call first. With `enabled` false this only forwards.
  KeyframeExtraction(FeatureService& features, KeyframeListener* next, bool enabled);
  ~KeyframeExtraction() override;
  KeyframeExtraction(const KeyframeExtraction&) = delete;
  KeyframeExtraction& operator=(const KeyframeExtraction&) = delete;

  void Enqueue(storage::Connection& c, const QueuedKeyframe& keyframe) override;
  void Admit(const std::string& map) override;
  void Enqueued(const std::string& map) override;
  KeyframeAnalysisStatus Await(std::int64_t keyframe_id) override;

  // Blocks until nothing is queued or running (tests); false on timeout.
  bool WaitIdle(double timeout_s);
  int extracted() const;  // keyframes done
  int failed() const;     // keyframes whose extraction threw (logged nowhere else)

 private:
  void Worker();

  FeatureService& features_;
  KeyframeListener* next_;
  bool enabled_;
  mutable std::mutex mutex_;
  std::condition_variable wake_, idle_;
  std::vector<std::pair<std::string, std::int64_t>> pending_;  // written, not yet committed
  std::deque<std::pair<std::string, std::int64_t>> queue_;
  bool running_ = false;
  bool stop_ = false;
  int extracted_ = 0, failed_ = 0;
  std::thread worker_;
};

}  // namespace anchordb::services
