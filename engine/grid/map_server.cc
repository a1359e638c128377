#include "engine/grid/map_server.h"

#include <yaml-cpp/yaml.h>

#include <charconv>
#include <cstring>
#include <cmath>

#include "engine/image/png_codec.h"
#include "schema/error.h"

namespace anchordb::engine {
namespace {

[[noreturn]] void BadYaml(const std::string& field, const std::string& what) {
  throw Error(ErrorCode::kInvalidArgument, "map yaml: " + field + ": " + what, "yaml." + field);
}

double YamlNumber(const YAML::Node& root, const char* key) {
  const YAML::Node n = root[key];
  if (!n) BadYaml(key, "required key is missing");
  double v = 0;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    BadYaml(key, "must be a number");
  }
  if (!std::isfinite(v)) BadYaml(key, "must be finite");
  return v;
}

std::string Shortest(double v) {
  char buf[64];
  auto res = std::to_chars(buf, buf + sizeof(buf), v);
  std::string s(buf, res.ptr);
  // Keep YAML floats recognisable as floats (map_server parses either way; this keeps "0" as "0.0" readable).
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

void SkipPgmSpace(std::string_view b, std::size_t& pos) {
  while (pos < b.size()) {
    if (b[pos] == '#') {
      while (pos < b.size() && b[pos] != '\n') ++pos;
    } else if (std::isspace(static_cast<unsigned char>(b[pos]))) {
      ++pos;
    } else {
      break;
    }
  }
}

long PgmInt(std::string_view b, std::size_t& pos) {
  SkipPgmSpace(b, pos);
  long v = 0;
  std::size_t start = pos;
  while (pos < b.size() && std::isdigit(static_cast<unsigned char>(b[pos])) && pos - start < 9) v = v * 10 + (b[pos++] - '0');
  if (pos == start) throw Error(ErrorCode::kInvalidArgument, "PGM header is malformed", "image");
  return v;
}

GreyImage DecodePgm(std::string_view b, std::size_t max_pixels) {
  const bool binary = b[1] == '5';
  std::size_t pos = 2;
  const long w = PgmInt(b, pos), h = PgmInt(b, pos), maxval = PgmInt(b, pos);
  if (w <= 0 || h <= 0) throw Error(ErrorCode::kInvalidArgument, "PGM has no pixels", "image");
  if (static_cast<std::size_t>(w) * static_cast<std::size_t>(h) > max_pixels) {
    throw Error(ErrorCode::kPayloadTooLarge, "map image has more than " + std::to_string(max_pixels) + " pixels", "image");
  }
  if (maxval != 255) {
    throw Error(ErrorCode::kUnprocessable, "PGM maxval " + std::to_string(maxval) + " is not supported (8-bit, 255 only)", "image");
  }
  GreyImage img{static_cast<int>(w), static_cast<int>(h), {}};
  const std::size_t n = static_cast<std::size_t>(w) * h;
  if (binary) {
    ++pos;  // exactly one whitespace byte after maxval
    if (b.size() < pos + n) throw Error(ErrorCode::kInvalidArgument, "PGM pixel data is truncated", "image");
    img.pixels.assign(b.begin() + pos, b.begin() + pos + n);
  } else {
    img.pixels.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
      const long v = PgmInt(b, pos);
      if (v > 255) throw Error(ErrorCode::kInvalidArgument, "PGM value above maxval", "image");
      img.pixels.push_back(static_cast<std::uint8_t>(v));
    }
  }
  return img;
}

}  // namespace

ParsedYaml ParseMapServerYamlUnchecked(std::string_view yaml_text);

ParsedYaml ParseMapServerYaml(std::string_view yaml_text) {
  try {
    return ParseMapServerYamlUnchecked(yaml_text);
  } catch (const YAML::Exception& e) {
    // Any conversion yaml-cpp refuses (a list where a string belongs, a complex key) is bad input, not a bug.
    throw Error(ErrorCode::kInvalidArgument, std::string("map yaml has an unexpected structure: ") + e.what(), "yaml");
  }
}

ParsedYaml ParseMapServerYamlUnchecked(std::string_view yaml_text) {
  YAML::Node root;
  try {
    root = YAML::Load(std::string(yaml_text));
  } catch (const YAML::Exception& e) {
    throw Error(ErrorCode::kInvalidArgument, std::string("map yaml does not parse: ") + e.what(), "yaml");
  }
  if (!root.IsMap()) throw Error(ErrorCode::kInvalidArgument, "map yaml must be a mapping of keys", "yaml");
  ParsedYaml out;
  MapServerMeta& m = out.meta;
  if (root["image"]) {
    try {
      m.image = root["image"].as<std::string>();
    } catch (const YAML::Exception&) {
      BadYaml("image", "must be a string");
    }
  }
  m.resolution_m = YamlNumber(root, "resolution");
  const YAML::Node origin = root["origin"];
  if (!origin || !origin.IsSequence() || origin.size() != 3) BadYaml("origin", "must be a list [x, y, yaw]");
  for (int i = 0; i < 3; ++i) {
    try {
      m.origin[i] = origin[i].as<double>();
    } catch (const YAML::Exception&) {
      BadYaml("origin", "must hold three numbers");
    }
    if (!std::isfinite(m.origin[i])) BadYaml("origin", "must be finite");
  }
  m.occupied_thresh = YamlNumber(root, "occupied_thresh");
  m.free_thresh = YamlNumber(root, "free_thresh");
  const double negate = root["negate"] ? YamlNumber(root, "negate") : 0.0;
  if (negate != 0.0 && negate != 1.0) BadYaml("negate", "must be 0 or 1");
  m.negate = static_cast<int>(negate);
  if (root["mode"]) {
    std::string mode;
    try {
      mode = root["mode"].as<std::string>();
    } catch (const YAML::Exception&) {
      BadYaml("mode", "must be trinary, scale or raw");
    }
    m.mode_given = true;
    if (mode == "trinary") m.mode = MapMode::kTrinary;
    else if (mode == "scale") m.mode = MapMode::kScale;
    else if (mode == "raw") m.mode = MapMode::kRaw;
    else BadYaml("mode", "must be trinary, scale or raw");
  }
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    if (key != "image" && key != "resolution" && key != "origin" && key != "occupied_thresh" &&
        key != "free_thresh" && key != "negate" && key != "mode") {
      out.ignored_keys.push_back(key);
    }
  }
  if (m.resolution_m <= 0.0 || m.resolution_m > 10.0) {
    throw Error(ErrorCode::kUnprocessable, "map yaml: resolution must be in (0, 10] m", "yaml.resolution");
  }
  if (!(m.free_thresh >= 0.0 && m.free_thresh < m.occupied_thresh && m.occupied_thresh <= 1.0)) {
    throw Error(ErrorCode::kUnprocessable, "map yaml: need 0 <= free_thresh < occupied_thresh <= 1",
                "yaml.occupied_thresh");
  }
  return out;
}

std::string EmitMapServerYaml(const MapServerMeta& m) {
  std::string y;
  y += "image: " + m.image + "\n";
  if (m.mode_given) y += std::string("mode: ") + MapModeName(m.mode) + "\n";
  y += "resolution: " + Shortest(m.resolution_m) + "\n";
  y += "origin: [" + Shortest(m.origin[0]) + ", " + Shortest(m.origin[1]) + ", " + Shortest(m.origin[2]) + "]\n";
  y += "negate: " + std::to_string(m.negate) + "\n";
  y += "occupied_thresh: " + Shortest(m.occupied_thresh) + "\n";
  y += "free_thresh: " + Shortest(m.free_thresh) + "\n";
  return y;
}

GreyImage DecodeMapImage(std::string_view bytes, std::size_t max_pixels) {
  if (bytes.size() >= 2 && bytes[0] == 'P' && (bytes[1] == '5' || bytes[1] == '2')) return DecodePgm(bytes, max_pixels);
  static constexpr unsigned char kPngMagic[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (bytes.size() < 8 || std::memcmp(bytes.data(), kPngMagic, 8) != 0) {
    throw Error(ErrorCode::kInvalidArgument, "map image must be a PGM (P5/P2) or PNG file", "image");
  }
  // Read the PNG header's size before decoding so an oversized image is refused without allocating it.
  if (const auto size = PngHeaderSize(bytes); size && static_cast<std::uint64_t>(size->first) * size->second > max_pixels) {
    throw Error(ErrorCode::kPayloadTooLarge, "map image has more than " + std::to_string(max_pixels) + " pixels", "image");
  }
  std::string why;
  const std::optional<PngImage> decoded = DecodePngImage(bytes, &why);
  if (!decoded) throw Error(ErrorCode::kInvalidArgument, "PNG could not be decoded (" + why + ")", "image");
  if (decoded->bit_depth != 8) throw Error(ErrorCode::kUnprocessable, "map PNG must have 8-bit channels", "image");
  GreyImage img{decoded->width, decoded->height, {}};
  img.pixels.resize(static_cast<std::size_t>(img.width) * img.height);
  const int channels = decoded->channels;
  const int colour_channels = (channels == 2 || channels == 4) ? channels - 1 : channels;  // alpha is not averaged
  for (int r = 0; r < decoded->height; ++r) {
    const std::uint8_t* row = decoded->bytes.data() + decoded->row_bytes() * static_cast<std::size_t>(r);
    for (int c = 0; c < decoded->width; ++c) {
      int sum = 0;
      for (int k = 0; k < colour_channels; ++k) sum += row[c * channels + k];
      img.pixels[static_cast<std::size_t>(r) * img.width + c] = static_cast<std::uint8_t>(sum / colour_channels);
    }
  }
  return img;
}

std::string EncodePgm(const GreyImage& image) {
  std::string out = "P5\n" + std::to_string(image.width) + " " + std::to_string(image.height) + "\n255\n";
  out.append(reinterpret_cast<const char*>(image.pixels.data()), image.pixels.size());
  return out;
}

std::string EncodePng(const GreyImage& image) {
  return EncodePngImage(PngImage{image.width, image.height, 1, 8, image.pixels}, 1);
}

GridGeometry GeometryOf(const GreyImage& image, const MapServerMeta& meta) {
  GridGeometry g;
  g.width_cells = image.width;
  g.height_cells = image.height;
  g.resolution_m = meta.resolution_m;
  g.origin_x_m = meta.origin[0];
  g.origin_y_m = meta.origin[1];
  g.origin_yaw_rad = meta.origin[2];
  return g;
}

MapServerMeta ScaleModeMeta(const GridGeometry& g, const std::string& image) {
  MapServerMeta meta;
  meta.image = image;
  meta.resolution_m = g.resolution_m;
  meta.origin[0] = g.origin_x_m, meta.origin[1] = g.origin_y_m, meta.origin[2] = g.origin_yaw_rad;
  meta.mode = MapMode::kScale;
  meta.mode_given = true;
  return meta;
}

OccupancyGrid ToOccupancy(const GreyImage& image, const MapServerMeta& meta) {
  OccupancyGrid grid(GeometryOf(image, meta), -1);
  for (int row = 0; row < image.height; ++row) {
    const int iy = image.height - 1 - row;  // image row 0 is the top of the map
    for (int ix = 0; ix < image.width; ++ix) {
      int grey = image.pixels[static_cast<std::size_t>(row) * image.width + ix];
      if (meta.negate) grey = 255 - grey;
      std::int8_t value;
      if (meta.mode == MapMode::kRaw) {
        value = static_cast<std::int8_t>(grey);
      } else {
        const double occ = (255 - grey) / 255.0;
        if (occ > meta.occupied_thresh) value = 100;
        else if (occ < meta.free_thresh) value = 0;
        else if (meta.mode == MapMode::kTrinary) value = -1;
        else value = static_cast<std::int8_t>(1 + 98 * (occ - meta.free_thresh) / (meta.occupied_thresh - meta.free_thresh));
      }
      grid.at(ix, iy) = value;
    }
  }
  return grid;
}

}  // namespace anchordb::engine
