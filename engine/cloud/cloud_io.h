#pragma once
// Point clouds in and out as PCD (ascii, binary, binary_compressed; PCL's PCDReader / PCDWriter) and PLY (ascii,
// binary little-endian; PCL's PLYReader / PLYWriter), behind Eigen/std types: only x, y, z are read and written,
// in the frame the caller names (metres). PCL is included only by engine/cloud/cloud_io.cc. PCL's PLY reader and
// writer work on files only: a PLY passes through one private temporary file, removed before the call returns.
// Errors: Error(kInvalidArgument, field "body") for bytes that do not decode (no x/y/z fields, a header that
// claims more data than the body holds, a wrong magic); Error(kPayloadTooLarge) for more than `max_points`.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

namespace anchordb::engine {

enum class CloudFormat { kPcdAscii, kPcdBinary, kPcdBinaryCompressed, kPlyAscii, kPlyBinary };

struct DecodedCloud {
  std::vector<Eigen::Vector3f> points;  // in file order, non-finite points included
  std::size_t width = 0, height = 0;    // as the header says (height 1 for unorganised clouds)
  Eigen::Vector3f sensor_origin = Eigen::Vector3f::Zero();  // PCD VIEWPOINT / PLY camera, when given
  bool has_sensor_origin = false;
};

// Decodes a PCD (any DATA kind) or PLY body; the kind is taken from its first bytes ("ply" or a PCD header).
DecodedCloud DecodeCloud(std::string_view bytes, std::size_t max_points);
std::string EncodeCloud(const std::vector<Eigen::Vector3f>& points, CloudFormat format);

}  // namespace anchordb::engine
