#pragma once
// The decisions the furniture segmentation service takes about a segment once it is found (thesis 5.3.1; issue 35:
// rules live in engine/): which keyframes are its evidence, how the shape model's verification refines the
// geometric prior, how a re-observed piece's category shares are averaged over its observations, which piece of the
// map a segment is, and the segmentation parameters for a cloud of OctoMap voxel centres.
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "engine/segmentation/footprint.h"
#include "engine/segmentation/furniture_segmentation.h"
#include "schema/types.h"

namespace anchordb::engine::segmentation {

// A keyframe as the evidence rule sees it: its camera, its pose in the map frame and its depth image (row-major,
// K.width x K.height, millimetres; 0 = no reading).
struct KeyframeView {
  std::int64_t keyframe = 0;
  PinholeIntrinsics K;
  Eigen::Isometry3d X_MapCamera = Eigen::Isometry3d::Identity();
  std::vector<std::uint16_t> depth_mm;
};

struct EvidenceRule {
  std::size_t samples = 50;          // about this many of the segment's points are tried per keyframe (every n-th)
  double min_depth_m = 0.1;          // a point at or nearer than this in front of the camera is not tried as seen
  double depth_tolerance_m = 0.1;    // |measured depth - point depth| below this: the keyframe saw the point
  int seen_share_denominator = 5;    // a keyframe is evidence when at least 1 / this of the tried points were seen
};

// The keyframes (ids, ascending) whose camera saw the segment: of its points sampled evenly, at least the rule's
// share project into the image within (min_depth_m, max_range_m] and match that keyframe's depth there (a point
// hidden behind a nearer surface does not count).
std::vector<std::int64_t> SegmentEvidence(const std::vector<Eigen::Vector3f>& points_m, const std::vector<KeyframeView>& keyframes,
                                          double max_range_m, const EvidenceRule& rule = {});

// p(f) over `category_ids`: the geometric prior times the shape model's verification scores (category id, score;
// thesis 4.1). A category the model gave no score keeps `unknown_floor` of its prior's weight, a scored one
// unknown_floor + score; the product is normalised. Without any positive score the prior is returned unchanged.
std::vector<double> PriorTimesVerification(std::vector<double> prior, const std::vector<std::string>& category_ids,
                                           const std::vector<std::pair<std::string, double>>& scores,
                                           double unknown_floor = 0.05);

// The category shares of a piece seen `observations` times before, after one more observation `p` (over
// `category_ids`): the running mean per category (a category the old shares lack counts as 0 there).
std::map<std::string, double> AverageCategoryShares(const std::map<std::string, double>& old_shares, double observations,
                                                    const std::vector<std::string>& category_ids, const std::vector<double>& p);

// Which piece of the map's furniture a segment is: the known footprint it overlaps most (intersection over union);
// at `match_iou` or more an operator's piece is kept as the operator entered it (kKeepOperatorPiece) and a perceived
// one takes the new observation (kUpdatePerceivedPiece), below it the segment is a new piece (kNewPiece, no index).
// Ties go to the first footprint.
enum class SegmentMatch { kNewPiece, kKeepOperatorPiece, kUpdatePerceivedPiece };
struct SegmentMatchResult {
  SegmentMatch match = SegmentMatch::kNewPiece;
  std::size_t index = 0;  // into `known`, unless kNewPiece
  double iou = 0.0;       // with the best-overlapping footprint (0 when none overlaps)
};
SegmentMatchResult MatchSegment(const Footprint& segment, const std::vector<Footprint>& known,
                                const std::vector<bool>& perceived, double match_iou);

// The parameters for a cloud of voxel centres `resolution_m` apart (the OctoMap source), when that is coarser than
// `p.voxel_m`: thinning keeps every centre (a leaf of half a voxel), the point counts meant for the default voxel
// scale with the area per point, and the neighbourhood radii reach across one voxel diagonal in a plane. Unchanged
// for a resolution at or below p.voxel_m.
SegmentationParams ParamsForVoxelCentres(SegmentationParams p, double resolution_m);

}  // namespace anchordb::engine::segmentation
