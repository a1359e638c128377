#include "services/octomap/octomap_settings.h"

namespace anchordb::services {

void BindOctomapSettings(SettingsBinder& b, OctomapSettings& s) {
  b.Bind("octomap_max_range_m", "default ray cut of a new map's occupancy tree: a ray longer than this updates free "
         "space up to it and marks no end voxel [m]", &s.max_range_m, 0.1, 1000);
  b.Bind("octomap_max_points", "most points of one cloud inserted into an occupancy tree", &s.max_points, 1, 5e7);
  b.Bind("octomap_max_query_points", "most points of one occupancy query", &s.max_query_points, 1, 1e7);
  b.Bind("octomap_max_voxels", "most voxels one box listing or cloud export returns", &s.max_voxels, 1, 5e7);
  b.Bind("octomap_from_keyframes", "every stored keyframe's depth, back-projected and ray-cast from its camera, "
         "updates the map's occupancy tree", &s.from_keyframes);
  b.Bind("octomap_keyframes_per_commit", "the keyframe feed stores a map's tree once per this many integrated keyframes "
         "and when the server stops (readers see every integrated keyframe at once; after a crash the keyframes past "
         "the stored tree are integrated again at start-up)", &s.keyframes_per_commit, 1, 1000);
}

}  // namespace anchordb::services
