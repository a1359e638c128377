// PCD and PLY through PCL's readers and writers (the only translation unit of engine/ that includes pcl/io).
#include "engine/cloud/cloud_io.h"

#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <pcl/PCLPointCloud2.h>
#include <pcl/common/io.h>
#include <pcl/conversions.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>

#include "schema/error.h"

namespace anchordb::engine {

namespace {

[[noreturn]] void Bad(const std::string& what) { throw Error(ErrorCode::kInvalidArgument, what, "body"); }

// A file of this process that is removed when the guard goes.
class TempFile {
 public:
  explicit TempFile(const char* suffix) {
    std::string pattern = (std::filesystem::temp_directory_path() / "anchordb-cloud-XXXXXX").string() + suffix;
    std::vector<char> buffer(pattern.begin(), pattern.end());
    buffer.push_back('\0');
    const int fd = mkstemps(buffer.data(), static_cast<int>(std::strlen(suffix)));
    if (fd < 0) throw Error(ErrorCode::kUnavailable, "no temporary file for a point cloud");
    close(fd);
    path_ = buffer.data();
  }
  ~TempFile() { std::remove(path_.c_str()); }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  const std::string& path() const { return path_; }
  void Write(std::string_view bytes) const {
    std::ofstream out(path_, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!out) throw Error(ErrorCode::kUnavailable, "could not write a temporary point cloud file");
  }
  std::string Read() const {
    std::ifstream in(path_, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return std::move(ss).str();
  }

 private:
  std::string path_;
};

// x, y and z once each, and every field inside a point: PCL's conversion copies by the header's offsets and sizes
// without checking them (a header with a garbled SIZE line read past the buffer: found by the fuzz target).
bool HasXyz(const pcl::PCLPointCloud2& cloud) {
  int found = 0;
  for (const auto& f : cloud.fields) {
    const std::uint64_t size = pcl::getFieldSize(f.datatype);
    if (size == 0 || std::uint64_t{f.offset} + size * std::max<std::uint32_t>(f.count, 1) > cloud.point_step) {
      return false;
    }
    if ((f.name == "x" || f.name == "y" || f.name == "z") && f.count == 1) ++found;
  }
  return found == 3;
}

void CheckSize(const pcl::PCLPointCloud2& header, std::size_t max_points) {
  const std::uint64_t points = std::uint64_t{header.width} * header.height;
  if (points > max_points) {
    throw Error(ErrorCode::kPayloadTooLarge,
                "the cloud holds " + std::to_string(points) + " points, over the limit of " + std::to_string(max_points),
                "body");
  }
}

DecodedCloud ToDecoded(const pcl::PCLPointCloud2& cloud, const Eigen::Vector4f& origin) {
  if (!HasXyz(cloud)) Bad("the cloud has no x, y and z fields, or its fields do not fit in a point");
  pcl::PointCloud<pcl::PointXYZ> xyz;
  // PCL 1.13's conversion takes &points[0] of the output even when it is empty (undefined behaviour): skip it then.
  if (std::uint64_t{cloud.width} * cloud.height > 0) pcl::fromPCLPointCloud2(cloud, xyz);
  DecodedCloud out;
  out.points.reserve(xyz.size());
  for (const auto& p : xyz) out.points.emplace_back(p.x, p.y, p.z);
  out.width = cloud.width;
  out.height = cloud.height;
  out.sensor_origin = origin.head<3>();
  out.has_sensor_origin = !origin.head<3>().isZero();
  return out;
}

// PCL's header reader sizes the point buffer from the header's numbers before anything can check them (a garbled
// header asked for 36 GB: found by the fuzz target). The numbers are read here first: the points (WIDTH x HEIGHT and
// POINTS) within `max_points`, and the buffer within what the body can fill (binary: its bytes; ascii: four bytes
// of values per character; LZF compression: at most about 100 times its bytes).
void CheckPcdHeaderNumbers(std::string_view bytes, std::size_t max_points) {
  // PCL acts on every line it reads (a POINTS line resizes the buffer), also after a DATA line it does not take for
  // the last one: the largest value of each key anywhere in the input counts. Lines are read in place; only the few
  // whose first word is a key are parsed.
  std::uint64_t width = 0, height = 0, points = 0, size = 0, count = 1, fields = 0;
  // PCL reads a line's numbers by stream extraction, not word by word: "1-23T05" is the two numbers 1 and -23 (found
  // by the fuzz target: a COUNT of -23 wrapped PCL's point size to 4 GB and its buffer to 154 GB). The numbers are
  // read here the same way, as many as the stream yields: a negative one is malformed, and one too large for 64 bits
  // counts as the cap (PCL's own parsing wraps it, found by the fuzz target: COUNT 8888...).
  static constexpr std::uint64_t kCap = 1u << 30;
  const auto largest = [](std::string_view key, std::string_view rest, std::uint64_t& into) {
    std::istringstream numbers{std::string(rest)};
    for (long long v = 0; numbers >> v || v != 0;) {
      if (v < 0) Bad("the PCD header's " + std::string(key) + " line holds a negative number");
      into = std::max(into, std::min(static_cast<std::uint64_t>(v), kCap));
      if (!numbers) break;  // an out-of-range number: extraction saturates it and fails
    }
    numbers.clear();  // the same text once more, word by word: the number of values (SIZE: of fields)
    numbers.seekg(0);
    std::uint64_t n = 0;
    for (std::string word; numbers >> word;) ++n;
    return n;
  };
  constexpr std::string_view kBlanks = " \t\r";  // PCL's word separators
  for (std::size_t at = 0; at < bytes.size();) {
    const std::size_t end = std::min(bytes.find('\n', at), bytes.size());
    std::string_view line = bytes.substr(at, end - at);
    at = end + 1;
    line.remove_prefix(std::min(line.find_first_not_of(kBlanks), line.size()));
    // PCL takes a line's first word by its prefix ("COUNTxyz" is a COUNT line).
    const std::string_view key = line.substr(0, line.find_first_of(kBlanks));
    const auto is = [&key](std::string_view name) { return key.substr(0, name.size()) == name; };
    std::uint64_t* into = is("WIDTH") ? &width : is("HEIGHT") ? &height : is("POINTS") ? &points
                        : is("SIZE")  ? &size  : is("COUNT")  ? &count  : nullptr;
    if (!into) continue;
    const std::uint64_t values = largest(key, line.substr(key.size()), *into);
    if (into == &size) fields = std::max(fields, values);
  }
  const std::uint64_t grid = width * std::max<std::uint64_t>(height, 1);
  if (grid > max_points) {
    throw Error(ErrorCode::kPayloadTooLarge,
                "the cloud holds " + std::to_string(grid) + " points, over the limit of " + std::to_string(max_points),
                "body");
  }
  // A header that lies (a POINTS above WIDTH x HEIGHT) is malformed, not large.
  if (points > grid) Bad("the PCD header's POINTS (" + std::to_string(points) + ") disagrees with its WIDTH x HEIGHT");
  // In double: the product of the header's numbers may not fit 64 bits.
  if (static_cast<double>(grid) * static_cast<double>(size) * static_cast<double>(count) * static_cast<double>(fields) >
      100.0 * static_cast<double>(bytes.size())) {
    Bad("the PCD header claims " + std::to_string(grid) + " points, more than the body can hold");
  }
}

DecodedCloud DecodePcd(std::string_view bytes, std::size_t max_points) {
  CheckPcdHeaderNumbers(bytes, max_points);
  pcl::PCDReader reader;
  pcl::PCLPointCloud2 cloud;
  Eigen::Vector4f origin;
  Eigen::Quaternionf orientation;
  int version = 0, data_type = 0;
  unsigned int data_idx = 0;
  std::istringstream stream{std::string(bytes)};
  if (reader.readHeader(stream, cloud, origin, orientation, version, data_type, data_idx) != 0) {
    Bad("the PCD header does not decode");
  }
  CheckSize(cloud, max_points);
  if (!HasXyz(cloud)) Bad("the cloud has no x, y and z fields, or its fields do not fit in a point");
  const std::uint64_t body_bytes = std::uint64_t{cloud.width} * cloud.height * cloud.point_step;
  // PCL sizes its buffer by POINTS and reads that many bytes of the body: a POINTS that disagrees with WIDTH x
  // HEIGHT read past the checked length (a heap overflow found by the fuzz target).
  if (cloud.data.size() != body_bytes) Bad("the PCD header's POINTS disagrees with its WIDTH x HEIGHT");
  if (data_type == 0) {
    // At least one character and a separator per value.
    if (body_bytes / std::max<std::uint32_t>(cloud.point_step, 1) * cloud.fields.size() * 2 > bytes.size()) {
      Bad("the PCD header claims more points than the body holds");
    }
    // readHeader reads ahead of the first point line. A body offset past the end (a header whose DATA line is not
    // one PCL knows reads as ascii) would leave the stream failed, and PCL's ascii reader loops until end-of-file,
    // which a failed stream never reaches: a request that hung a server thread, found by the fuzz target.
    if (data_idx > bytes.size()) Bad("the PCD header claims more data than the body holds");
    stream.clear();
    stream.seekg(data_idx);
    if (!stream) Bad("the PCD ascii body cannot be reached");
    if (reader.readBodyASCII(stream, cloud, version) != 0) Bad("the PCD ascii body does not decode");
  } else {
    if (data_idx > bytes.size()) Bad("the PCD header claims more data than the body holds");
    if (data_type == 1 && data_idx + body_bytes > bytes.size()) {
      Bad("the PCD header claims " + std::to_string(body_bytes) + " bytes of points; the body holds " +
          std::to_string(bytes.size() - data_idx));
    }
    if (data_type == 2) {
      if (data_idx + 8 > bytes.size()) Bad("the PCD compressed body is truncated");
      std::uint32_t compressed = 0, uncompressed = 0;
      std::memcpy(&compressed, bytes.data() + data_idx, 4);
      std::memcpy(&uncompressed, bytes.data() + data_idx + 4, 4);
      if (std::uint64_t{data_idx} + 8 + compressed > bytes.size() || uncompressed != body_bytes) {
        Bad("the PCD compressed body does not match its header");
      }
    }
    if (reader.readBodyBinary(reinterpret_cast<const unsigned char*>(bytes.data()), cloud, version, data_type == 2,
                              data_idx) != 0) {
      Bad("the PCD binary body does not decode");
    }
  }
  if (cloud.data.size() != body_bytes) Bad("the PCD body does not hold the points its header claims");
  return ToDecoded(cloud, origin);
}

DecodedCloud DecodePly(std::string_view bytes, std::size_t max_points) {
  TempFile file(".ply");
  file.Write(bytes);
  pcl::PLYReader reader;
  pcl::PCLPointCloud2 cloud;
  Eigen::Vector4f origin;
  Eigen::Quaternionf orientation;
  int version = 0, data_type = 0;
  unsigned int data_idx = 0;
  if (reader.readHeader(file.path(), cloud, origin, orientation, version, data_type, data_idx) != 0) {
    Bad("the PLY header does not decode");
  }
  CheckSize(cloud, max_points);
  if (reader.read(file.path(), cloud, origin, orientation, version) != 0) Bad("the PLY body does not decode");
  if (cloud.data.size() != std::size_t{cloud.width} * cloud.height * cloud.point_step) {
    Bad("the PLY body does not hold the vertices its header claims");
  }
  return ToDecoded(cloud, origin);
}

}  // namespace

DecodedCloud DecodeCloud(std::string_view bytes, std::size_t max_points) {
  if (bytes.substr(0, 3) == "ply") return DecodePly(bytes, max_points);
  if (bytes.find("DATA ") == std::string_view::npos || bytes.find("FIELDS ") == std::string_view::npos) {
    Bad("the body is neither a PCD (FIELDS / DATA header) nor a PLY file");
  }
  try {
    return DecodePcd(bytes, max_points);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    // PCL's header reader throws the standard library's exceptions on some garbled headers (found by the fuzz
    // target): the client's bad input, not a server fault.
    Bad(std::string("the PCD header does not decode (") + e.what() + ")");
  }
}

std::string EncodeCloud(const std::vector<Eigen::Vector3f>& points, CloudFormat format) {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  cloud.reserve(points.size());
  for (const Eigen::Vector3f& p : points) cloud.emplace_back(p.x(), p.y(), p.z());
  cloud.width = static_cast<std::uint32_t>(cloud.size());
  cloud.height = 1;
  cloud.is_dense = false;
  const bool ply = format == CloudFormat::kPlyAscii || format == CloudFormat::kPlyBinary;
  TempFile file(ply ? ".ply" : ".pcd");
  int rc = 0;
  if (points.empty() && !ply) {
    // PCL refuses to write an empty PCD; its header alone is the empty cloud.
    pcl::PCLPointCloud2 empty;
    pcl::toPCLPointCloud2(cloud, empty);
    std::string header = pcl::PCDWriter().generateHeaderBinary(empty, Eigen::Vector4f::Zero(),
                                                               Eigen::Quaternionf::Identity());
    if (header.find("DATA ") == std::string::npos) {
      header += format == CloudFormat::kPcdAscii ? "DATA ascii\n" : "DATA binary\n";
    }
    return header;
  }
  switch (format) {
    case CloudFormat::kPcdAscii: rc = pcl::io::savePCDFileASCII(file.path(), cloud); break;
    case CloudFormat::kPcdBinary: rc = pcl::io::savePCDFileBinary(file.path(), cloud); break;
    case CloudFormat::kPcdBinaryCompressed: rc = pcl::io::savePCDFileBinaryCompressed(file.path(), cloud); break;
    case CloudFormat::kPlyAscii: rc = pcl::io::savePLYFileASCII(file.path(), cloud); break;
    case CloudFormat::kPlyBinary: rc = pcl::io::savePLYFileBinary(file.path(), cloud); break;
  }
  if (rc != 0) throw Error(ErrorCode::kInternal, "PCL could not write the point cloud");
  return file.Read();
}

}  // namespace anchordb::engine
