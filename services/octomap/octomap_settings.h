#pragma once
// Settings of the octomap capability (bound in octomap_settings.cc; shown by --help and GET /v1/settings).
#include <cstddef>

#include "schema/settings.h"

namespace anchordb::services {

struct OctomapSettings {
  double max_range_m = 5.0;              // default ray cut of a new map's tree [m]
  int max_points = 2000000;       // points per inserted cloud
  int max_query_points = 100000;    // points per occupancy query
  int max_voxels = 200000;         // voxels per box listing
  bool from_keyframes = false;           // octomap_from_keyframes: every stored keyframe updates the map's tree
  // octomap_keyframes_per_commit: the keyframe feed stores a map's tree once per this many integrated keyframes
  // (and when the server stops). The tree is derived from stored keyframes: after a crash the keyframes past the
  // stored tree's `keyframes_through` are integrated again at start-up, so nothing is lost by waiting.
  int keyframes_per_commit = 10;
};

void BindOctomapSettings(SettingsBinder& b, OctomapSettings& settings);

}  // namespace anchordb::services
