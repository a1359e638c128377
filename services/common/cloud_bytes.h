#pragma once
// A point cloud handed out as PCD or PLY bytes, with its point count.
#include <vector>

#include <Eigen/Core>

#include "engine/cloud/cloud_io.h"
#include "services/common/exported_bytes.h"

namespace anchordb::services {

ExportedLayer CloudBytes(const std::vector<Eigen::Vector3f>& points, engine::CloudFormat format);

}  // namespace anchordb::services
