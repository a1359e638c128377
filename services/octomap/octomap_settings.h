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
};

void BindOctomapSettings(SettingsBinder& b, OctomapSettings& settings);

}  // namespace anchordb::services
