#pragma once
// `anchordb import tum`: feeds a TUM RGB-D sequence (Sturm et al. 2012, the benchmark's file layout) into a map
// through the services, as a robot would have: one scene model per imported depth frame, opened at the frame's
// ground-truth camera pose, given the frame and closed (its begin and end keyframes), and the map's OctoMap brought
// up to date from the stored keyframes (OctomapService::Follow, octomap_from_keyframes forced on for the run).
//
// Layout read from the sequence directory: depth.txt ("timestamp path" per line, '#' comments), the 16-bit
// grayscale depth PNGs it names (relative to the directory; `depth_scale` units per metre, TUM: 5000), and
// groundtruth.txt ("timestamp tx ty tz qx qy qz qw": the pose of the camera's optical frame, z forward, in the
// world frame, which becomes the map frame unchanged). rgb.txt is not needed (the memory keeps depth only). Each
// depth frame takes the ground-truth pose of the nearest stamp, if within `max_dt_s` (TUM's associate.py: 0.02 s).
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "schema/types.h"
#include "server/config.h"

namespace anchordb::server {

struct TumImportOptions {
  std::string dir;          // the sequence directory
  std::string map;          // an existing map
  int every = 1;            // import every N-th depth frame of depth.txt
  int max_frames = 0;       // at most this many frames (0: all)
  PinholeIntrinsics camera; // width, height from the first PNG; fx, fy, cx, cy (default: Freiburg 1)
  double depth_scale = 5000.0;  // depth units per metre
  double max_dt_s = 0.02;   // largest |depth stamp - ground-truth stamp| accepted [s]
  bool merge = false;       // let each new scene model merge the earlier ones near it (3.3.3); off: independent
};

// One line of depth.txt / rgb.txt, and of groundtruth.txt (pose of the optical frame in the world frame).
struct TumImage {
  double stamp_s = 0;
  std::string path;
};
struct TumPose {
  double stamp_s = 0;
  Pose3 X_WorldCamera;
};

// Parsers of the two list kinds. Throw std::invalid_argument naming the file and line of a bad line (wrong field
// count, a number that does not parse or is not finite, a quaternion far from unit norm).
std::vector<TumImage> ParseTumImageList(std::istream& in, const std::string& file);
std::vector<TumPose> ParseTumGroundTruth(std::istream& in, const std::string& file);

// The Freiburg 1 / 2 / 3 depth cameras' intrinsics of the benchmark's documentation ("fr1", "fr2", "fr3"); throws
// std::invalid_argument for another name.
PinholeIntrinsics TumCamera(const std::string& name);

// Runs the import (see above) on the database of `config`, printing progress lines and a summary to `out`. Throws
// std::invalid_argument for missing files, bad lines, an unknown map or unusable PNGs (nothing is stored: every
// file is checked before the first frame), anchordb::Error when a service refuses a frame.
void ImportTum(const Config& config, const TumImportOptions& options, std::ostream& out);

// `anchordb import tum ...` arguments after "tum": the import's own flags, the rest is settings (--db ...).
int ImportTumCommand(const std::vector<std::string>& args, const std::map<std::string, std::string>& environment);

}  // namespace anchordb::server
