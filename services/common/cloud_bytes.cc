// A point cloud as exported bytes.
#include "services/common/cloud_bytes.h"

namespace anchordb::services {

ExportedLayer CloudBytes(const std::vector<Eigen::Vector3f>& points, engine::CloudFormat format) {
  ExportedLayer out;
  const bool ply = format == engine::CloudFormat::kPlyAscii || format == engine::CloudFormat::kPlyBinary;
  out.format = ply ? BytesFormat::kPly : BytesFormat::kPcd;
  out.body = engine::EncodeCloud(points, format);
  out.points = points.size();
  return out;
}

}  // namespace anchordb::services
