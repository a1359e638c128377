#include "storage/layer_codec.h"

#include <cmath>
#include <cstring>

#include "schema/error.h"
#include "storage/blob_codec.h"
#include "schema/json_io.h"

namespace anchordb::storage {

using json::Json;

namespace {

Json MapServerMetaToJson(const MapServerMeta& m) {
  return {{"image", m.image},         {"resolution", m.resolution_m},
          {"origin", {m.origin[0], m.origin[1], m.origin[2]}},
          {"negate", m.negate},       {"occupied_thresh", m.occupied_thresh},
          {"free_thresh", m.free_thresh}, {"mode", MapModeName(m.mode)}, {"mode_given", m.mode_given}};
}

MapServerMeta MapServerMetaFromJson(const Json& j) {
  MapServerMeta m;
  m.image = j.at("image").get<std::string>();
  m.resolution_m = j.at("resolution").get<double>();
  for (int i = 0; i < 3; ++i) m.origin[i] = j.at("origin").at(i).get<double>();
  m.negate = j.at("negate").get<int>();
  m.occupied_thresh = j.at("occupied_thresh").get<double>();
  m.free_thresh = j.at("free_thresh").get<double>();
  const std::string mode = j.at("mode").get<std::string>();
  m.mode = mode == "scale" ? MapMode::kScale : mode == "raw" ? MapMode::kRaw : MapMode::kTrinary;
  m.mode_given = j.at("mode_given").get<bool>();
  return m;
}

GridGeometry GeometryFromJson(const Json& g) {
  GridGeometry geometry;
  geometry.width_cells = g.at("width_cells").get<int>();
  geometry.height_cells = g.at("height_cells").get<int>();
  geometry.resolution_m = g.at("resolution_m").get<double>();
  geometry.origin_x_m = g.at("origin").at(0).get<double>();
  geometry.origin_y_m = g.at("origin").at(1).get<double>();
  geometry.origin_yaw_rad = g.at("origin").at(2).get<double>();
  if (geometry.width_cells < 0 || geometry.height_cells < 0) throw std::out_of_range("negative grid size");
  return geometry;
}

FuseOp FuseOpFromName(const std::string& name) {
  for (FuseOp op : {FuseOp::kAnd, FuseOp::kOr, FuseOp::kAndNot, FuseOp::kXor}) {
    if (name == FuseOpName(op)) return op;
  }
  throw std::out_of_range("unknown fuse op '" + name + "'");
}

// The metadata of `record`, which must be of `kind`, read by `decode`; any missing or mistyped field is kInternal.
template <typename Decode>
auto DecodeMeta(const LayerRecord& record, LayerKind kind, Decode decode) {
  if (record.kind != kind) {
    throw Error(ErrorCode::kInternal, "layer '" + record.name + "' is a " + LayerKindName(record.kind) +
                                          " layer, not a " + LayerKindName(kind) + " layer");
  }
  const Json meta = Json::parse(record.meta_json, nullptr, false);
  if (meta.is_discarded() || !meta.is_object()) {
    throw Error(ErrorCode::kInternal, "stored metadata of layer '" + record.name + "' is not valid JSON");
  }
  try {
    return decode(meta);
  } catch (const std::exception& e) {  // nlohmann's type and range errors, and the checks above
    throw Error(ErrorCode::kInternal, "stored metadata of layer '" + record.name + "' is malformed: " + e.what());
  }
}

std::vector<std::uint32_t> GridShape(const GridGeometry& g) {
  return {static_cast<std::uint32_t>(g.height_cells), static_cast<std::uint32_t>(g.width_cells)};
}

template <typename T>
std::vector<T> DecodeCells(const LayerRecord& record, BlobElement element, const GridGeometry& g) {
  const DecodedBlob blob = DecodeBlob(record.data);
  if (blob.element != element || blob.shape.size() != 2 || static_cast<int>(blob.shape[0]) != g.height_cells ||
      static_cast<int>(blob.shape[1]) != g.width_cells || blob.bytes.size() != g.CellCount() * sizeof(T)) {
    throw Error(ErrorCode::kInternal, "stored data of layer '" + record.name + "' does not match its metadata");
  }
  std::vector<T> cells(g.CellCount());
  std::memcpy(cells.data(), blob.bytes.data(), blob.bytes.size());
  return cells;
}

template <typename T>
void CheckCellCount(const std::vector<T>& cells, const GridGeometry& g) {
  if (cells.size() != g.CellCount()) throw Error(ErrorCode::kInternal, "layer cells do not match the layer's geometry");
}

}  // namespace

// ---------------------------------------------------------------- the stored metadata documents

namespace {

Json MetaToJson(const OccupancyLayerMeta& m) {
  return {{"geometry", json::ToJson(m.geometry)}, {"map_server", MapServerMetaToJson(m.map_server)},
          {"ignored_yaml_keys", m.ignored_yaml_keys}};
}

Json MetaToJson(const ProbabilityLayerMeta& m) {
  return {{"geometry", json::ToJson(m.geometry)}, {"base", m.base}, {"log_odds", json::ToJson(m.log_odds)},
          {"observations", m.observations}};
}

Json MetaToJson(const FusedLayerMeta& m) {
  Json operands = Json::array();
  for (const FuseOperand& o : m.operands) operands.push_back({{"layer", o.layer}, {"threshold", o.threshold}});
  return {{"geometry", json::ToJson(m.geometry)}, {"op", FuseOpName(m.op)}, {"operands", operands}};
}

Json MetaToJson(const LabelLayerMeta& m) {
  Json labels = Json::object();
  for (const auto& [id, name] : m.labels) labels[std::to_string(id)] = name;
  return {{"geometry", json::ToJson(m.geometry)}, {"base", m.base}, {"labels", labels}};
}

}  // namespace

std::string EncodeLayerMeta(const OccupancyLayerMeta& meta) { return MetaToJson(meta).dump(); }
std::string EncodeLayerMeta(const ProbabilityLayerMeta& meta) { return MetaToJson(meta).dump(); }
std::string EncodeLayerMeta(const FusedLayerMeta& meta) { return MetaToJson(meta).dump(); }
std::string EncodeLayerMeta(const LabelLayerMeta& meta) { return MetaToJson(meta).dump(); }

// ---------------------------------------------------------------- encoders

void EncodeLayer(const OccupancyLayer& layer, LayerRecord& record) {
  CheckCellCount(layer.image_pixels, layer.meta.geometry);
  record.kind = LayerKind::kOccupancy;
  record.meta_json = EncodeLayerMeta(layer.meta);
  record.data = EncodeBlob(BlobElement::kU8, GridShape(layer.meta.geometry), AsBytes(layer.image_pixels));
}

void EncodeLayer(const ProbabilityLayer& layer, LayerRecord& record) {
  CheckCellCount(layer.log_odds, layer.meta.geometry);
  record.kind = LayerKind::kProbability;
  record.meta_json = EncodeLayerMeta(layer.meta);
  // Level 1: observation updates rewrite this blob on every call; speed matters more than the last percent.
  record.data = EncodeBlob(BlobElement::kF32, GridShape(layer.meta.geometry), AsBytes(layer.log_odds), 1);
}

void EncodeLayer(const FusedLayerMeta& meta, LayerRecord& record) {
  record.kind = LayerKind::kFused;
  record.meta_json = EncodeLayerMeta(meta);
  record.data.clear();
}

void EncodeLayer(const LabelLayer& layer, LayerRecord& record) {
  CheckCellCount(layer.label_ids, layer.meta.geometry);
  record.kind = LayerKind::kLabel;
  record.meta_json = EncodeLayerMeta(layer.meta);
  record.data = EncodeBlob(BlobElement::kU16, GridShape(layer.meta.geometry), AsBytes(layer.label_ids));
}

// ---------------------------------------------------------------- decoders

GridGeometry DecodeGeometry(const LayerRecord& record) {
  return DecodeMeta(record, record.kind, [](const Json& j) { return GeometryFromJson(j.at("geometry")); });
}

OccupancyLayerMeta DecodeOccupancyMeta(const LayerRecord& record) {
  return DecodeMeta(record, LayerKind::kOccupancy, [](const Json& j) {
    OccupancyLayerMeta m;
    m.geometry = GeometryFromJson(j.at("geometry"));
    m.map_server = MapServerMetaFromJson(j.at("map_server"));
    m.ignored_yaml_keys = j.at("ignored_yaml_keys").get<std::vector<std::string>>();
    return m;
  });
}

ProbabilityLayerMeta DecodeProbabilityMeta(const LayerRecord& record) {
  return DecodeMeta(record, LayerKind::kProbability, [](const Json& j) {
    ProbabilityLayerMeta m;
    m.geometry = GeometryFromJson(j.at("geometry"));
    m.base = j.at("base").get<std::string>();
    const Json& p = j.at("log_odds");
    m.log_odds.hit_probability = p.at("hit").get<double>();
    m.log_odds.miss_probability = p.at("miss").get<double>();
    m.log_odds.clamp_min_probability = p.at("clamp_min").get<double>();
    m.log_odds.clamp_max_probability = p.at("clamp_max").get<double>();
    m.observations = j.value("observations", std::int64_t{0});
    return m;
  });
}

FusedLayerMeta DecodeFusedMeta(const LayerRecord& record) {
  return DecodeMeta(record, LayerKind::kFused, [](const Json& j) {
    FusedLayerMeta m;
    m.geometry = GeometryFromJson(j.at("geometry"));
    m.op = FuseOpFromName(j.at("op").get<std::string>());
    for (const Json& o : j.at("operands")) {
      m.operands.push_back({o.at("layer").get<std::string>(), o.at("threshold").get<double>()});
    }
    return m;
  });
}

LabelLayerMeta DecodeLabelMeta(const LayerRecord& record) {
  return DecodeMeta(record, LayerKind::kLabel, [](const Json& j) {
    LabelLayerMeta m;
    m.geometry = GeometryFromJson(j.at("geometry"));
    m.base = j.at("base").get<std::string>();
    for (const auto& [key, name] : j.at("labels").items()) {
      const int id = std::atoi(key.c_str());
      if (id < 1 || id > 65535 || std::to_string(id) != key) throw std::out_of_range("label id '" + key + "'");
      m.labels[id] = name.get<std::string>();
    }
    return m;
  });
}

OccupancyLayer DecodeOccupancyLayer(const LayerRecord& record) {
  OccupancyLayer layer{DecodeOccupancyMeta(record), {}};
  layer.image_pixels = DecodeCells<std::uint8_t>(record, BlobElement::kU8, layer.meta.geometry);
  return layer;
}

ProbabilityLayer DecodeProbabilityLayer(const LayerRecord& record) {
  ProbabilityLayer layer{DecodeProbabilityMeta(record), {}};
  layer.log_odds = DecodeCells<float>(record, BlobElement::kF32, layer.meta.geometry);
  return layer;
}

LabelLayer DecodeLabelLayer(const LayerRecord& record) {
  LabelLayer layer{DecodeLabelMeta(record), {}};
  layer.label_ids = DecodeCells<std::uint16_t>(record, BlobElement::kU16, layer.meta.geometry);
  return layer;
}

}  // namespace anchordb::storage
