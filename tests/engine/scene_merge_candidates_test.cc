// Candidate selection for the merge (thesis 3.3.3, engine/scene/merge_candidates.h): the cheap checks, the frustum
// overlap of a probed background, and the order and limits of the selection.
#include "engine/scene/merge_candidates.h"

#include <gtest/gtest.h>

#include <map>

namespace anchordb::engine {
namespace scene_merge_candidates_test {

constexpr std::int64_t kDayNs = 24LL * 3600 * 1'000'000'000;
const PinholeIntrinsics kK{64, 48, 60.0, 60.0, 31.5, 23.5};

// A camera at p looking along +x of the map (optical z = map x, optical x = map -y, optical y = map -z).
Eigen::Isometry3d LookingAlongX(const Eigen::Vector3d& p, double yaw_rad = 0.0) {
  Eigen::Matrix3d R;
  R << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix() * R;
  X.translation() = p;
  return X;
}

// A wall `depth_m` in front of the camera.
EarlierBackground Wall(const Eigen::Isometry3d& X, float depth_m = 2.0f) {
  return {kK, X, std::vector<float>(static_cast<std::size_t>(kK.width) * kK.height, depth_m)};
}

EarlierModel Finished(std::int64_t id, std::int64_t started_ns, Eigen::Vector3d p = Eigen::Vector3d::Zero()) {
  return {id, false, 10, started_ns, p};
}

TEST(SceneMergeCandidatesTest, DefaultsAreThoseOfTheSettings) {
  const MergeCandidateParams p;
  EXPECT_EQ(p.max_candidates, 5);
  EXPECT_DOUBLE_EQ(p.max_age_s, 30.0 * 24 * 3600);
  EXPECT_DOUBLE_EQ(p.candidate_radius_m, 6.0);
  EXPECT_DOUBLE_EQ(p.min_overlap, 0.05);
  EXPECT_DOUBLE_EQ(p.frustum_far_m, 5.0);
  EXPECT_EQ(kMergeCandidatesExamined, 50);
}

TEST(SceneMergeCandidatesTest, OnlyFinishedPersistedRecentNearbyModelsMayMerge) {
  const std::int64_t now = 100 * kDayNs;
  const MergeCandidateParams p;
  const Eigen::Vector3d here(0, 0, 1);
  EXPECT_TRUE(MayMerge(Finished(1, now - kDayNs), here, now, p));
  EarlierModel observing = Finished(1, now - kDayNs);
  observing.observing = true;
  EXPECT_FALSE(MayMerge(observing, here, now, p));
  EarlierModel empty = Finished(1, now - kDayNs);
  empty.persisted_frames = 0;
  EXPECT_FALSE(MayMerge(empty, here, now, p));
  EXPECT_TRUE(MayMerge(Finished(1, now - 30 * kDayNs), here, now, p));  // exactly max_age_s old
  EXPECT_FALSE(MayMerge(Finished(1, now - 30 * kDayNs - 1), here, now, p));
  EXPECT_TRUE(MayMerge(Finished(1, now, {5.9, 0, 1}), here, now, p));
  EXPECT_FALSE(MayMerge(Finished(1, now, {6.1, 0, 1}), here, now, p));
}

TEST(SceneMergeCandidatesTest, OverlapOfTheProbedBackgroundWithTheNewFrustum) {
  const Eigen::Isometry3d X = LookingAlongX({0, 0, 1});
  EXPECT_GT(ProbeOverlap(Wall(X), kK, X, 5.0), 0.8);  // the same view (probes on the image border may fall out)
  EXPECT_DOUBLE_EQ(ProbeOverlap(Wall(X), kK, LookingAlongX({0, 0, 1}, M_PI), 5.0), 0.0);  // turned around
  EXPECT_DOUBLE_EQ(ProbeOverlap(Wall(X, 4.0f), kK, LookingAlongX({-2, 0, 1}), 5.0), 0.0);  // the wall beyond far
  // Turned by the horizontal half field of view (28 deg): about half the wall is still in view.
  const double half = ProbeOverlap(Wall(X), kK, LookingAlongX({0, 0, 1}, std::atan(32.0 / 60.0)), 5.0);
  EXPECT_GT(half, 0.3);
  EXPECT_LT(half, 0.7);
}

TEST(SceneMergeCandidatesTest, NewestFirstAtMostMaxCandidatesLoadingOnlyWhatIsNeeded) {
  const Eigen::Isometry3d X = LookingAlongX({0, 0, 1});
  const std::int64_t now = 10 * kDayNs;
  std::vector<EarlierModel> newest_first;
  for (std::int64_t id = 9; id >= 1; --id) newest_first.push_back(Finished(id, now - id, {0, 0, 1}));
  newest_first[1].observing = true;  // 8: not loaded
  std::vector<std::int64_t> loaded;
  const auto source = [&](std::int64_t id) -> std::optional<EarlierBackground> {
    loaded.push_back(id);
    if (id == 7) return std::nullopt;                                       // forgotten
    if (id == 6) return Wall(LookingAlongX({0, 0, 1}, M_PI));               // facing away: no overlap
    return Wall(X);
  };
  MergeCandidateParams p;
  p.max_candidates = 3;
  const std::vector<MergeCandidate> c = SelectMergeCandidates(newest_first, kK, X, now, p, source);
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c[0].id, 9);
  EXPECT_EQ(c[1].id, 5);
  EXPECT_EQ(c[2].id, 4);
  EXPECT_DOUBLE_EQ(c[0].overlap, ProbeOverlap(Wall(X), kK, X, p.frustum_far_m));
  EXPECT_EQ(loaded, (std::vector<std::int64_t>{9, 7, 6, 5, 4}));  // 8 failed the cheap checks; nothing after the 3rd
}

TEST(SceneMergeCandidatesTest, MinOverlapApplies) {
  const Eigen::Isometry3d X = LookingAlongX({0, 0, 1});
  const Eigen::Isometry3d turned = LookingAlongX({0, 0, 1}, std::atan(32.0 / 60.0));
  const std::vector<EarlierModel> one = {Finished(1, 0, {0, 0, 1})};
  const auto source = [&](std::int64_t) -> std::optional<EarlierBackground> { return Wall(X); };
  MergeCandidateParams p;
  EXPECT_EQ(SelectMergeCandidates(one, kK, turned, 0, p, source).size(), 1u);
  p.min_overlap = 0.9;
  EXPECT_TRUE(SelectMergeCandidates(one, kK, turned, 0, p, source).empty());
}

}  // namespace
}  // namespace anchordb::engine
