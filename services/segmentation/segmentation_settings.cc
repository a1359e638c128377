#include "services/segmentation/segmentation_settings.h"

namespace anchordb::services {

void BindSegmentationSettings(SettingsBinder& b, SegmentationSettings& s) {
  b.Bind("segmentation_max_cloud_points", "most points of a room cloud given to the furniture segmentation (a client's "
         "cloud body, or the OctoMap's occupied leaves); more is refused (413)", &s.max_cloud_points, 1, 1e9);
}

}  // namespace anchordb::services
