// The layers table and its child tables (migrations/*/0019): a layer's metadata in typed columns, with the lists of
// its kind (fused operands, label names, ignored YAML keys) in one child table each. meta_list_rows on the layer row
// counts those rows, so a layer without any is read in one statement.
#include <optional>
#include <type_traits>

#include "schema/error.h"
#include "storage/repositories.h"

namespace anchordb::storage {

std::optional<LayerKind> LayerKindFromName(const std::string& n) {
  if (n == "occupancy") return LayerKind::kOccupancy;
  if (n == "probability") return LayerKind::kProbability;
  if (n == "fused") return LayerKind::kFused;
  if (n == "label") return LayerKind::kLabel;
  return std::nullopt;
}

namespace {

// The columns every read selects, in the order ReadLayerRow reads them; `data` follows when it is loaded.
constexpr const char* kLayerColumns =
    "map_id, name, kind, version, created_ns, updated_ns, coalesce(length(data), 0), width_cells, height_cells, "
    "resolution_m, origin_x_m, origin_y_m, origin_yaw_rad, base_layer, hit_probability, miss_probability, "
    "clamp_min_probability, clamp_max_probability, observations, fuse_op, yaml_image, yaml_resolution_m, "
    "yaml_origin_x_m, yaml_origin_y_m, yaml_origin_yaw_rad, yaml_negate, yaml_occupied_thresh, yaml_free_thresh, "
    "yaml_mode, yaml_mode_given, meta_list_rows";
constexpr int kDataColumn = 31;

// The typed columns a layer of each kind fills (the others stay NULL), and the child rows of its list.
struct MetaColumns {
  GridGeometry geometry;
  std::optional<std::string> base;
  std::optional<ProbabilityLayerMeta> probability;
  std::optional<FuseOp> fuse_op;
  std::optional<MapServerMeta> map_server;
  std::int64_t list_rows = 0;
};

MetaColumns ColumnsOf(const StoredLayerMeta& meta) {
  MetaColumns c;
  std::visit(
      [&](const auto& m) {
        using M = std::decay_t<decltype(m)>;
        c.geometry = m.geometry;
        if constexpr (std::is_same_v<M, OccupancyLayerMeta>) {
          c.map_server = m.map_server;
          c.list_rows = static_cast<std::int64_t>(m.ignored_yaml_keys.size());
        } else if constexpr (std::is_same_v<M, ProbabilityLayerMeta>) {
          c.base = m.base;
          c.probability = m;
        } else if constexpr (std::is_same_v<M, FusedLayerMeta>) {
          c.fuse_op = m.op;
          c.list_rows = static_cast<std::int64_t>(m.operands.size());
        } else {
          c.base = m.base;
          c.list_rows = static_cast<std::int64_t>(m.labels.size());
        }
      },
      meta);
  return c;
}

template <typename T>
void BindOr(Statement& s, int index, const std::optional<T>& v) {
  if (v) s.Bind(index, *v);
  else s.BindNull(index);
}

// Binds the metadata columns of `meta` at parameters first .. first + 23, in the order of kMetaAssignments.
void BindMeta(Statement& s, int first, const StoredLayerMeta& meta) {
  const MetaColumns c = ColumnsOf(meta);
  const GridGeometry& g = c.geometry;
  s.Bind(first, std::int64_t{g.width_cells}).Bind(first + 1, std::int64_t{g.height_cells});
  s.Bind(first + 2, g.resolution_m).Bind(first + 3, g.origin_x_m).Bind(first + 4, g.origin_y_m);
  s.Bind(first + 5, g.origin_yaw_rad);
  if (c.base) s.Bind(first + 6, std::string_view(*c.base)); else s.BindNull(first + 6);
  const auto& p = c.probability;
  BindOr(s, first + 7, p ? std::optional(p->log_odds.hit_probability) : std::nullopt);
  BindOr(s, first + 8, p ? std::optional(p->log_odds.miss_probability) : std::nullopt);
  BindOr(s, first + 9, p ? std::optional(p->log_odds.clamp_min_probability) : std::nullopt);
  BindOr(s, first + 10, p ? std::optional(p->log_odds.clamp_max_probability) : std::nullopt);
  BindOr(s, first + 11, p ? std::optional(p->observations) : std::nullopt);
  if (c.fuse_op) s.Bind(first + 12, std::string_view(FuseOpName(*c.fuse_op))); else s.BindNull(first + 12);
  const auto& y = c.map_server;
  if (y) s.Bind(first + 13, std::string_view(y->image)); else s.BindNull(first + 13);
  BindOr(s, first + 14, y ? std::optional(y->resolution_m) : std::nullopt);
  for (int i = 0; i < 3; ++i) BindOr(s, first + 15 + i, y ? std::optional(y->origin[i]) : std::nullopt);
  BindOr(s, first + 18, y ? std::optional<std::int64_t>(y->negate) : std::nullopt);
  BindOr(s, first + 19, y ? std::optional(y->occupied_thresh) : std::nullopt);
  BindOr(s, first + 20, y ? std::optional(y->free_thresh) : std::nullopt);
  if (y) s.Bind(first + 21, std::string_view(MapModeName(y->mode))); else s.BindNull(first + 21);
  BindOr(s, first + 22, y ? std::optional<std::int64_t>(y->mode_given ? 1 : 0) : std::nullopt);
  s.Bind(first + 23, c.list_rows);
}

constexpr const char* kMetaAssignments =
    "width_cells = ?, height_cells = ?, resolution_m = ?, origin_x_m = ?, origin_y_m = ?, origin_yaw_rad = ?, "
    "base_layer = ?, hit_probability = ?, miss_probability = ?, clamp_min_probability = ?, "
    "clamp_max_probability = ?, observations = ?, fuse_op = ?, yaml_image = ?, yaml_resolution_m = ?, "
    "yaml_origin_x_m = ?, yaml_origin_y_m = ?, yaml_origin_yaw_rad = ?, yaml_negate = ?, yaml_occupied_thresh = ?, "
    "yaml_free_thresh = ?, yaml_mode = ?, yaml_mode_given = ?, meta_list_rows = ?";

Error MalformedLayerRow(const std::string& layer, const std::string& what) {
  return Error(ErrorCode::kInternal, "stored metadata of layer '" + layer + "' is malformed: " + what);
}

double RequiredDouble(const Statement& s, int column, const std::string& layer) {
  if (s.IsNull(column)) throw MalformedLayerRow(layer, "a value of its kind is missing");
  return s.Double(column);
}

FuseOp FuseOpFromName(const std::string& name, const std::string& layer) {
  for (FuseOp op : {FuseOp::kAnd, FuseOp::kOr, FuseOp::kAndNot, FuseOp::kXor}) {
    if (name == FuseOpName(op)) return op;
  }
  throw MalformedLayerRow(layer, "unknown fuse op '" + name + "'");
}

MapMode MapModeFromName(const std::string& name, const std::string& layer) {
  for (MapMode mode : {MapMode::kTrinary, MapMode::kScale, MapMode::kRaw}) {
    if (name == MapModeName(mode)) return mode;
  }
  throw MalformedLayerRow(layer, "unknown map mode '" + name + "'");
}

// The metadata columns (7..29) of a layer row of `kind`, without the lists.
StoredLayerMeta ReadMeta(const Statement& s, LayerKind kind, const std::string& layer) {
  GridGeometry g;
  g.width_cells = static_cast<int>(s.Int(7));
  g.height_cells = static_cast<int>(s.Int(8));
  g.resolution_m = s.Double(9);
  g.origin_x_m = s.Double(10);
  g.origin_y_m = s.Double(11);
  g.origin_yaw_rad = s.Double(12);
  const auto base = [&] {
    if (s.IsNull(13)) throw MalformedLayerRow(layer, "no base layer");
    return s.Text(13);
  };
  switch (kind) {
    case LayerKind::kOccupancy: {
      OccupancyLayerMeta m{g, {}, {}};
      if (s.IsNull(20) || s.IsNull(25) || s.IsNull(28) || s.IsNull(29)) throw MalformedLayerRow(layer, "no map_server values");
      m.map_server.image = s.Text(20);
      m.map_server.resolution_m = RequiredDouble(s, 21, layer);
      for (int i = 0; i < 3; ++i) m.map_server.origin[i] = RequiredDouble(s, 22 + i, layer);
      m.map_server.negate = static_cast<int>(s.Int(25));
      m.map_server.occupied_thresh = RequiredDouble(s, 26, layer);
      m.map_server.free_thresh = RequiredDouble(s, 27, layer);
      m.map_server.mode = MapModeFromName(s.Text(28), layer);
      m.map_server.mode_given = s.Int(29) != 0;
      return m;
    }
    case LayerKind::kProbability: {
      if (s.IsNull(18)) throw MalformedLayerRow(layer, "no observation count");
      LogOddsParams p{RequiredDouble(s, 14, layer), RequiredDouble(s, 15, layer), RequiredDouble(s, 16, layer),
                      RequiredDouble(s, 17, layer)};
      return ProbabilityLayerMeta{g, base(), p, s.Int(18)};
    }
    case LayerKind::kFused:
      if (s.IsNull(19)) throw MalformedLayerRow(layer, "no fuse op");
      return FusedLayerMeta{g, FuseOpFromName(s.Text(19), layer), {}};
    case LayerKind::kLabel: return LabelLayerMeta{g, base(), {}};
  }
  throw MalformedLayerRow(layer, "unknown kind");
}

struct LayerRow {
  LayerRecord record;
  std::int64_t list_rows = 0;  // child rows still to read
};

LayerRow ReadLayerRow(const Statement& s, bool with_data) {
  LayerRow row;
  LayerRecord& l = row.record;
  l.map_id = s.Text(0);
  l.name = s.Text(1);
  const std::optional<LayerKind> kind = LayerKindFromName(s.Text(2));
  if (!kind) throw MalformedLayerRow(l.name, "unknown kind '" + s.Text(2) + "'");
  l.kind = *kind;
  l.version = s.Int(3);
  l.created_ns = s.Int(4);
  l.updated_ns = s.Int(5);
  l.data_bytes = s.Int(6);
  l.meta = ReadMeta(s, l.kind, l.name);
  row.list_rows = s.Int(30);
  if (with_data) l.data = s.Blob(kDataColumn);
  return row;
}

// Reads the child rows of the list of `l`'s kind into its metadata.
void ReadLists(Connection& c, LayerRecord& l) {
  if (auto* fused = std::get_if<FusedLayerMeta>(&l.meta)) {
    Statement s(c, "SELECT operand, threshold FROM layer_fuse_operands WHERE map_id = ? AND layer = ? ORDER BY position");
    s.Bind(1, l.map_id).Bind(2, l.name);
    while (s.Step()) fused->operands.push_back({s.Text(0), s.Double(1)});
  } else if (auto* label = std::get_if<LabelLayerMeta>(&l.meta)) {
    Statement s(c, "SELECT label_id, name FROM layer_label_names WHERE map_id = ? AND layer = ? ORDER BY label_id");
    s.Bind(1, l.map_id).Bind(2, l.name);
    while (s.Step()) label->labels[static_cast<int>(s.Int(0))] = s.Text(1);
  } else if (auto* occupancy = std::get_if<OccupancyLayerMeta>(&l.meta)) {
    Statement s(c, "SELECT yaml_key FROM layer_ignored_yaml_keys WHERE map_id = ? AND layer = ? ORDER BY position");
    s.Bind(1, l.map_id).Bind(2, l.name);
    while (s.Step()) occupancy->ignored_yaml_keys.push_back(s.Text(0));
  }
}

// Writes the child rows of `l`'s list (after the old ones were deleted, or for a new layer).
void WriteLists(Connection& c, const LayerRecord& l) {
  if (const auto* fused = std::get_if<FusedLayerMeta>(&l.meta)) {
    for (std::size_t i = 0; i < fused->operands.size(); ++i) {
      Statement(c, "INSERT INTO layer_fuse_operands (map_id, layer, position, operand, threshold) VALUES (?, ?, ?, ?, ?)")
          .Bind(1, l.map_id).Bind(2, l.name).Bind(3, static_cast<std::int64_t>(i)).Bind(4, fused->operands[i].layer)
          .Bind(5, fused->operands[i].threshold).Run();
    }
  } else if (const auto* label = std::get_if<LabelLayerMeta>(&l.meta)) {
    for (const auto& [id, name] : label->labels) {
      Statement(c, "INSERT INTO layer_label_names (map_id, layer, label_id, name) VALUES (?, ?, ?, ?)")
          .Bind(1, l.map_id).Bind(2, l.name).Bind(3, std::int64_t{id}).Bind(4, name).Run();
    }
  } else if (const auto* occupancy = std::get_if<OccupancyLayerMeta>(&l.meta)) {
    for (std::size_t i = 0; i < occupancy->ignored_yaml_keys.size(); ++i) {
      Statement(c, "INSERT INTO layer_ignored_yaml_keys (map_id, layer, position, yaml_key) VALUES (?, ?, ?, ?)")
          .Bind(1, l.map_id).Bind(2, l.name).Bind(3, static_cast<std::int64_t>(i)).Bind(4, occupancy->ignored_yaml_keys[i]).Run();
    }
  }
}

// Deletes the child rows of `l`'s list (the kind of a stored layer never changes; probability layers have none).
void DeleteLists(Connection& c, const LayerRecord& l) {
  const char* table = std::holds_alternative<FusedLayerMeta>(l.meta)      ? "layer_fuse_operands"
                      : std::holds_alternative<LabelLayerMeta>(l.meta)     ? "layer_label_names"
                      : std::holds_alternative<OccupancyLayerMeta>(l.meta) ? "layer_ignored_yaml_keys"
                                                                            : nullptr;
  if (!table) return;
  Statement(c, std::string("DELETE FROM ") + table + " WHERE map_id = ? AND layer = ?").Bind(1, l.map_id).Bind(2, l.name).Run();
}

void CheckKindAgrees(const LayerRecord& l) {
  if (static_cast<std::size_t>(l.kind) != l.meta.index()) {
    throw Error(ErrorCode::kInternal, "layer '" + l.name + "': its metadata is not of its kind");
  }
}

std::string SelectLayer(bool with_data) {
  return std::string("SELECT ") + kLayerColumns + (with_data ? ", data" : "") + " FROM layers WHERE map_id = ? AND name = ?";
}

}  // namespace

void InsertLayer(Connection& c, const LayerRecord& l, const std::vector<std::string>& depends_on) {
  CheckKindAgrees(l);
  if (FindLayerRow(c, l.map_id, l.name)) {
    throw Error(ErrorCode::kConflict, "layer '" + l.name + "' already exists in map '" + l.map_id + "'", "layer");
  }
  std::string placeholders = "?";
  for (int i = 1; i < 31; ++i) placeholders += ", ?";
  Statement s(c, "INSERT INTO layers (map_id, name, kind, data, version, created_ns, updated_ns, width_cells, "
                 "height_cells, resolution_m, origin_x_m, origin_y_m, origin_yaw_rad, base_layer, hit_probability, "
                 "miss_probability, clamp_min_probability, clamp_max_probability, observations, fuse_op, yaml_image, "
                 "yaml_resolution_m, yaml_origin_x_m, yaml_origin_y_m, yaml_origin_yaw_rad, yaml_negate, "
                 "yaml_occupied_thresh, yaml_free_thresh, yaml_mode, yaml_mode_given, meta_list_rows) VALUES (" +
                     placeholders + ")");
  s.Bind(1, l.map_id).Bind(2, l.name).Bind(3, std::string_view(LayerKindName(l.kind)));
  if (l.data.empty()) s.BindNull(4); else s.BindBlob(4, l.data);
  s.Bind(5, l.version).Bind(6, l.created_ns).Bind(7, l.updated_ns);
  BindMeta(s, 8, l.meta);
  s.Run();
  WriteLists(c, l);
  for (const std::string& d : depends_on) {
    Statement(c, "INSERT INTO layer_dependencies (map_id, layer, depends_on) VALUES (?, ?, ?) ON CONFLICT DO NOTHING")
        .Bind(1, l.map_id).Bind(2, l.name).Bind(3, d).Run();
  }
}

std::optional<LayerRecordRow> FindLayerRow(Connection& c, const std::string& map_id, const std::string& name) {
  Statement s(c, SelectLayer(false));
  s.Bind(1, map_id).Bind(2, name);
  if (!s.Step()) return std::nullopt;
  LayerRow row = ReadLayerRow(s, false);
  return LayerRecordRow{std::move(row.record), row.list_rows == 0};
}

std::optional<LayerRecord> FindLayer(Connection& c, const std::string& map_id, const std::string& name, bool with_data) {
  std::optional<LayerRow> row;
  {
    Statement s(c, SelectLayer(with_data));
    s.Bind(1, map_id).Bind(2, name);
    if (!s.Step()) return std::nullopt;
    row = ReadLayerRow(s, with_data);
  }
  if (row->list_rows > 0) ReadLists(c, row->record);
  return std::move(row->record);
}

std::vector<LayerRecord> ListLayers(Connection& c, const std::string& map_id) {
  std::vector<LayerRow> rows;
  {
    Statement s(c, std::string("SELECT ") + kLayerColumns + " FROM layers WHERE map_id = ? ORDER BY name");
    s.Bind(1, map_id);
    while (s.Step()) rows.push_back(ReadLayerRow(s, false));
  }
  std::vector<LayerRecord> out;
  for (LayerRow& row : rows) {
    if (row.list_rows > 0) ReadLists(c, row.record);
    out.push_back(std::move(row.record));
  }
  return out;
}

void UpdateLayer(Connection& c, const LayerRecord& l, std::int64_t expected_version) {
  CheckKindAgrees(l);
  Statement s(c, std::string("UPDATE layers SET ") + kMetaAssignments +
                     ", data = ?, version = ?, updated_ns = ? WHERE map_id = ? AND name = ? AND version = ? AND kind = ?");
  BindMeta(s, 1, l.meta);
  if (l.data.empty()) s.BindNull(25); else s.BindBlob(25, l.data);
  s.Bind(26, l.version).Bind(27, l.updated_ns).Bind(28, l.map_id).Bind(29, l.name).Bind(30, expected_version);
  s.Bind(31, std::string_view(LayerKindName(l.kind))).Run();
  if (c.Changes() != 1) {
    throw Error(ErrorCode::kConflict, "layer '" + l.name + "' changed concurrently (expected version " +
                                          std::to_string(expected_version) + ")");
  }
  DeleteLists(c, l);
  WriteLists(c, l);
}

std::vector<std::string> LayerDependents(Connection& c, const std::string& map_id, const std::string& name) {
  Statement s(c, "SELECT layer FROM layer_dependencies WHERE map_id = ? AND depends_on = ? ORDER BY layer");
  s.Bind(1, map_id).Bind(2, name);
  std::vector<std::string> out;
  while (s.Step()) out.push_back(s.Text(0));
  return out;
}

bool DeleteLayer(Connection& c, const std::string& map_id, const std::string& name) {
  Statement(c, "DELETE FROM layers WHERE map_id = ? AND name = ?").Bind(1, map_id).Bind(2, name).Run();
  return c.Changes() > 0;
}

}  // namespace anchordb::storage
