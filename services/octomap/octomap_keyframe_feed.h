#pragma once
// Keeps the maps' trees following the memory (OctomapService::Follow) after each stored keyframe: a KeyframeListener
// placed in front of the analysis queue. It passes everything on to `next` and, once `next` has the keyframe's
// analysis queued, wakes its own worker thread for the map, so the ray casting runs outside the scene's write
// transaction and the request does not wait for it. With octomap_from_keyframes off it only passes on (removal
// events still clear voxels, at the next keyframe of the map). Failures are counted and logged to stderr, never
// thrown into the scene service.
#include <condition_variable>
#include <mutex>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "services/octomap/octomap_service.h"
#include "services/scene/keyframe_listener.h"

namespace anchordb::services {

class OctomapKeyframeFeed : public KeyframeListener {
 public:
  OctomapKeyframeFeed(OctomapService& octomap, KeyframeListener& next);
  ~OctomapKeyframeFeed() override;  // finishes the map being followed, joins, then stores the pending trees
  OctomapKeyframeFeed(const OctomapKeyframeFeed&) = delete;
  OctomapKeyframeFeed& operator=(const OctomapKeyframeFeed&) = delete;

  void Enqueue(storage::Connection& c, const QueuedKeyframe& keyframe) override;
  void Admit(const std::string& map) override;
  void Enqueued(const std::string& map) override;
  KeyframeAnalysisStatus Await(std::int64_t keyframe_id) override;

  // Follows each of `maps` once (the server's start: keyframes stored after a tree's last commit, e.g. before a
  // kill -9, are integrated again). Does not wait.
  void FollowAtStart(const std::vector<std::string>& maps);
  // Blocks until no map waits to be followed (tests, and callers that read the tree right after a keyframe).
  void Drain();
  // Totals since start.
  FollowReport totals() const;
  std::size_t failures() const;

 private:
  void Worker();

  OctomapService& octomap_;
  KeyframeListener& next_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::map<std::string, std::int64_t> staged_;   // map -> newest keyframe of a transaction not yet committed
  std::map<std::string, std::int64_t> pending_;  // map -> newest committed keyframe to wait for, then follow
  bool busy_ = false;
  bool stopping_ = false;
  FollowReport totals_;
  std::size_t failures_ = 0;
  std::thread worker_;  // started at the first keyframe
};

}  // namespace anchordb::services
