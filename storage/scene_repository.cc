#include "storage/scene_repository.h"

#include <cctype>
#include <charconv>

#include "storage/blob_codec.h"
#include "storage/dialect.h"
#include "storage/scene_merge_columns.h"
#include "schema/error.h"

namespace anchordb::storage {
namespace {

// The row's own columns, then the merge report's (scene_merge_columns.h) from kMergeReportAt; the state blobs follow
// when they are loaded.
const std::string kSceneColumns =
    std::string("id, map_id, status, superseded_by, width_px, height_px, fx_px, fy_px, cx_px, cy_px, x_m, y_m, z_m, qx, "
                "qy, qz, qw, beta, dynamic_mode, depth_scale, started_ns, ended_ns, last_frame_ns, frames, "
                "state_version, forgotten_ns, pose_covariance, pose_covariance_f64, ") + merge_report::kColumns;
constexpr int kMergeReportAt = 28;
constexpr int kStateAt = kMergeReportAt + merge_report::kColumnCount;

struct SceneRow {
  SceneRecord scene;
  std::int64_t merge_list_rows = 0;  // still to load
};

using Covariance = std::array<double, 36>;

std::string EncodeCovariance(const Covariance& row_major) {
  const std::string_view bytes(reinterpret_cast<const char*>(row_major.data()), sizeof row_major);
  return EncodeBlob(BlobElement::kF64, {6, 6}, bytes);
}

std::optional<Covariance> DecodeCovariance(std::string_view blob) {
  std::optional<std::vector<double>> v;
  try {
    v = DecodeArray<double>(blob, BlobElement::kF64, 36);
  } catch (const Error&) {  // not an envelope
    return std::nullopt;
  }
  if (!v) return std::nullopt;
  Covariance out;
  std::copy(v->begin(), v->end(), out.begin());
  return out;
}

// The column of schemas 0010-0017: a JSON array of 36 numbers, as nlohmann-json wrote it. Read as what it is, a
// bracketed list of numbers separated by commas (blanks allowed); anything else reads as no covariance.
std::optional<Covariance> ReadLegacyCovariance(std::string_view text) {
  std::size_t at = 0;
  const auto skip_blanks = [&] {
    while (at < text.size() && std::isspace(static_cast<unsigned char>(text[at]))) ++at;
  };
  const auto expect = [&](char ch) {
    skip_blanks();
    if (at == text.size() || text[at] != ch) return false;
    ++at;
    return true;
  };
  Covariance out;
  if (!expect('[')) return std::nullopt;
  for (std::size_t n = 0; n < out.size(); ++n) {
    if (n > 0 && !expect(',')) return std::nullopt;
    skip_blanks();
    const auto [end, ec] = std::from_chars(text.data() + at, text.data() + text.size(), out[n]);
    if (ec != std::errc()) return std::nullopt;
    at = static_cast<std::size_t>(end - text.data());
  }
  if (!expect(']')) return std::nullopt;
  skip_blanks();
  return at == text.size() ? std::optional<Covariance>(out) : std::nullopt;
}

SceneRow ReadScene(Statement& s, bool with_state) {
  SceneRow row;
  SceneRecord& r = row.scene;
  r.id = s.Int(0);
  r.map_id = s.Text(1);
  r.status = s.Text(2);
  r.superseded_by = OptionalInt(s, 3);
  r.camera = {static_cast<int>(s.Int(4)), static_cast<int>(s.Int(5)), s.Double(6), s.Double(7), s.Double(8), s.Double(9)};
  r.pose.position_m = {s.Double(10), s.Double(11), s.Double(12)};
  r.pose.orientation = Eigen::Quaterniond(s.Double(16), s.Double(13), s.Double(14), s.Double(15));
  r.beta = s.Double(17);
  r.dynamic_mode = s.Text(18);
  r.depth_scale = s.Double(19);
  r.started_ns = s.Int(20);
  r.ended_ns = OptionalInt(s, 21);
  r.last_frame_ns = OptionalInt(s, 22);
  r.frames = s.Int(23);
  r.state_version = s.Int(24);
  r.forgotten_ns = OptionalInt(s, 25);
  if (!s.IsNull(27)) r.pose_covariance = DecodeCovariance(s.Blob(27));
  else if (!s.IsNull(26)) r.pose_covariance = ReadLegacyCovariance(s.Text(26));
  row.merge_list_rows = merge_report::Read(s, kMergeReportAt, r.merge_report);
  if (with_state) {
    r.background = s.Blob(kStateAt);
    r.weight = s.Blob(kStateAt + 1);
    r.labels = s.Blob(kStateAt + 2);
  }
  return row;
}

SceneRecord Complete(Connection& c, SceneRow row) {
  if (row.merge_list_rows > 0) merge_report::ReadLists(c, row.scene.id, row.scene.merge_report);
  return std::move(row.scene);
}

}  // namespace

std::int64_t InsertScene(Connection& c, const SceneRecord& r) {
  std::string placeholders = "?";
  for (int i = 1; i < 20 + merge_report::kColumnCount; ++i) placeholders += ", ?";
  Statement s(c, "INSERT INTO scene_models (map_id, status, width_px, height_px, fx_px, fy_px, cx_px, cy_px, x_m, y_m, "
                 "z_m, qx, qy, qz, qw, beta, dynamic_mode, depth_scale, started_ns, pose_covariance_f64, " +
                     std::string(merge_report::kColumns) + ") VALUES (" + placeholders + ") RETURNING id");
  const Eigen::Vector3d& t = r.pose.position_m;
  const Eigen::Quaterniond& q = r.pose.orientation;
  s.Bind(1, r.map_id).Bind(2, r.status).Bind(3, std::int64_t{r.camera.width}).Bind(4, std::int64_t{r.camera.height})
      .Bind(5, r.camera.fx).Bind(6, r.camera.fy).Bind(7, r.camera.cx).Bind(8, r.camera.cy).Bind(9, t.x()).Bind(10, t.y())
      .Bind(11, t.z()).Bind(12, q.x()).Bind(13, q.y()).Bind(14, q.z()).Bind(15, q.w()).Bind(16, r.beta)
      .Bind(17, r.dynamic_mode).Bind(18, r.depth_scale).Bind(19, r.started_ns);
  if (r.pose_covariance) s.BindBlob(20, EncodeCovariance(*r.pose_covariance));
  else s.BindNull(20);
  merge_report::Bind(s, 21, r.merge_report);
  const std::int64_t id = s.RunReturningId();
  merge_report::ReplaceLists(c, id, r.merge_report);
  return id;
}

std::optional<SceneRecord> FindScene(Connection& c, const std::string& map_id, std::int64_t id, bool with_state) {
  const std::string sql = "SELECT " + kSceneColumns + (with_state ? ", background, weight, labels" : "") +
                          " FROM scene_models WHERE map_id = ? AND id = ?";
  std::optional<SceneRow> row;
  {
    Statement s(c, sql);
    s.Bind(1, map_id).Bind(2, id);
    if (!s.Step()) return std::nullopt;
    row = ReadScene(s, with_state);
  }
  return Complete(c, std::move(*row));
}

std::vector<SceneRecord> ListScenes(Connection& c, const std::string& map_id, const SceneFilter& f) {
  std::string sql = "SELECT " + kSceneColumns + " FROM scene_models m WHERE map_id = ?1";
  if (f.status) sql += " AND status = ?2";
  if (f.near_m) {
    sql += " AND " + PointInBox(c.engine(), {"scene_models_rtree", "id", "m.id", "m.x_m", "m.y_m", "m.z_m"},
                                {"?3 + ?6", "?4 + ?6", "?3 - ?6", "?4 - ?6", "?5 + ?6", "?5 - ?6"}) +
           " AND (x_m - ?3) * (x_m - ?3) + (y_m - ?4) * (y_m - ?4) + (z_m - ?5) * (z_m - ?5) <= ?6 * ?6";
  }
  sql += " ORDER BY id DESC LIMIT ?7";
  Statement s(c, sql);
  s.Bind(1, map_id);
  if (f.status) s.Bind(2, *f.status);
  if (f.near_m) s.Bind(3, f.near_m->x()).Bind(4, f.near_m->y()).Bind(5, f.near_m->z()).Bind(6, f.radius_m);
  s.Bind(7, static_cast<std::int64_t>(f.limit));
  std::vector<SceneRow> rows;
  while (s.Step()) rows.push_back(ReadScene(s, false));
  std::vector<SceneRecord> out;
  out.reserve(rows.size());
  for (SceneRow& row : rows) out.push_back(Complete(c, std::move(row)));
  return out;
}

void UpdateSceneState(Connection& c, const SceneRecord& r, std::int64_t expected) {
  std::string assignments;
  for (std::string_view rest = merge_report::kColumns; !rest.empty();) {
    const std::size_t comma = rest.find(", ");
    assignments += ", " + std::string(rest.substr(0, comma)) + " = ?";
    rest = comma == std::string_view::npos ? std::string_view() : rest.substr(comma + 2);
  }
  Statement s(c, "UPDATE scene_models SET background = ?, weight = ?, labels = ?, frames = ?, last_frame_ns = ?, "
                 "state_version = ?" + assignments + " WHERE id = ? AND state_version = ?");
  s.BindBlob(1, r.background).BindBlob(2, r.weight).BindBlob(3, r.labels).Bind(4, r.frames);
  BindOptional(s, 5, r.last_frame_ns);
  s.Bind(6, r.state_version);
  merge_report::Bind(s, 7, r.merge_report);
  s.Bind(7 + merge_report::kColumnCount, r.id).Bind(8 + merge_report::kColumnCount, expected).Run();
  if (c.Changes() != 1) {
    throw Error(ErrorCode::kConflict, "scene model " + std::to_string(r.id) + " was changed concurrently");
  }
  // The report's lists (a checkpoint every SceneLimits::persist_every_frames frames rewrites their few rows).
  merge_report::ReplaceLists(c, r.id, r.merge_report);
}

void UpdateSceneStatus(Connection& c, std::int64_t id, const std::string& status, std::optional<std::int64_t> ended_ns,
                       std::optional<std::int64_t> superseded_by) {
  Statement s(c, "UPDATE scene_models SET status = ?, ended_ns = coalesce(?, ended_ns), "
                 "superseded_by = coalesce(?, superseded_by) WHERE id = ?");
  s.Bind(1, status);
  BindOptional(s, 2, ended_ns);
  BindOptional(s, 3, superseded_by);
  s.Bind(4, id).Run();
}

std::int64_t InsertKeyframe(Connection& c, const KeyframeRecord& k) {
  Statement s(c, "INSERT INTO keyframes (map_id, scene_id, kind, stamp_ns, width, height, depth, background, raw_bytes, "
                 "stored_bytes, pinned, action_layer) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?) RETURNING id");
  s.Bind(1, k.map_id).Bind(2, k.scene_id).Bind(3, k.kind).Bind(4, k.stamp_ns).Bind(5, static_cast<std::int64_t>(k.width))
      .Bind(6, static_cast<std::int64_t>(k.height)).BindBlob(7, k.depth).BindBlob(8, k.background).Bind(9, k.raw_bytes)
      .Bind(10, k.stored_bytes).Bind(11, static_cast<std::int64_t>(k.pinned)).Bind(12, k.action_layer);
  return s.RunReturningId();
}

namespace {
KeyframeRecord ReadKeyframe(Statement& s, bool with_images) {
  KeyframeRecord k;
  k.id = s.Int(0);
  k.map_id = s.Text(1);
  k.scene_id = s.Int(2);
  k.kind = s.Text(3);
  k.stamp_ns = s.Int(4);
  k.width = static_cast<int>(s.Int(5));
  k.height = static_cast<int>(s.Int(6));
  k.raw_bytes = s.Int(7);
  k.stored_bytes = s.Int(8);
  k.pinned = s.Int(9) != 0;
  k.action_layer = s.Int(10);
  k.relevance = s.Double(11);
  if (with_images) {
    k.depth = s.Blob(12);
    k.background = s.Blob(13);
  }
  return k;
}
constexpr const char* kKeyframeColumns =
    "id, map_id, scene_id, kind, stamp_ns, width, height, raw_bytes, stored_bytes, pinned, action_layer, relevance";
}  // namespace

std::optional<KeyframeRecord> FindKeyframe(Connection& c, const std::string& map_id, std::int64_t id, bool with_images) {
  Statement s(c, std::string("SELECT ") + kKeyframeColumns + (with_images ? ", depth, background" : "") +
                     " FROM keyframes WHERE map_id = ? AND id = ?");
  s.Bind(1, map_id).Bind(2, id);
  if (!s.Step()) return std::nullopt;
  return ReadKeyframe(s, with_images);
}

std::vector<KeyframeRecord> ListKeyframes(Connection& c, const std::string& map_id, std::int64_t scene_id) {
  Statement s(c, std::string("SELECT ") + kKeyframeColumns +
                     " FROM keyframes WHERE map_id = ? AND scene_id = ? ORDER BY stamp_ns, id");
  s.Bind(1, map_id).Bind(2, scene_id);
  std::vector<KeyframeRecord> out;
  while (s.Step()) out.push_back(ReadKeyframe(s, false));
  return out;
}

}  // namespace anchordb::storage
