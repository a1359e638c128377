#pragma once
// Reading the shared real data (../shared/data, or $ANCHORDB_SHARED_DATA) in the realdata tests.
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace anchordb::testing {

// `relative` below the shared data folder.
inline std::string SharedDataPath(const std::string& relative) {
  const char* env = std::getenv("ANCHORDB_SHARED_DATA");
  return std::string(env ? env : "../shared/data") + "/" + relative;
}

inline std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// P5, maxval 65535, big-endian samples.
inline std::vector<std::uint16_t> ReadPgm16(const std::string& path, int& width, int& height) {
  const std::string b = ReadFile(path);
  std::istringstream header(b);
  std::string magic;
  int maxval = 0;
  header >> magic >> width >> height >> maxval;
  if (magic != "P5" || maxval != 65535) throw std::runtime_error(path + " is not a 16-bit PGM");
  const std::size_t offset = static_cast<std::size_t>(header.tellg()) + 1;
  std::vector<std::uint16_t> px(static_cast<std::size_t>(width) * height);
  if (b.size() < offset + 2 * px.size()) throw std::runtime_error(path + " is truncated");
  for (std::size_t i = 0; i < px.size(); ++i) {
    px[i] = static_cast<std::uint16_t>((static_cast<std::uint8_t>(b[offset + 2 * i]) << 8) |
                                       static_cast<std::uint8_t>(b[offset + 2 * i + 1]));
  }
  return px;
}

}  // namespace anchordb::testing
