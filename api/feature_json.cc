#include "api/feature_json.h"

#include <cstdio>
#include <sstream>

#include "api/route_params.h"

namespace anchordb::api {

using namespace params;

namespace {

constexpr std::size_t kMaxDescriptor = 4096;

std::vector<float> AsDescriptor(const Json& v, const std::string& field) {
  if (!v.is_array() || v.empty() || v.size() > kMaxDescriptor) {
    throw Error(ErrorCode::kInvalidArgument, "descriptor must be an array of 1 to 4096 numbers", field);
  }
  std::vector<float> out;
  out.reserve(v.size());
  for (const Json& x : v) {
    if (!x.is_number()) throw Error(ErrorCode::kInvalidArgument, "descriptor values must be numbers", field);
    const double d = x.get<double>();
    if (!std::isfinite(d) || std::abs(d) > 3e38) throw Error(ErrorCode::kInvalidArgument, "descriptor values must be finite", field);
    out.push_back(static_cast<float>(d));
  }
  return out;
}

Eigen::Vector3d AsPoint3(const Json& v, const std::string& field) {
  if (!v.is_array() || v.size() != 3) throw Error(ErrorCode::kInvalidArgument, field + " must be [x, y, z] in metres", field);
  Eigen::Vector3d p;
  for (int i = 0; i < 3; ++i) p[i] = json::AsFiniteNumber(v[static_cast<std::size_t>(i)], field);
  return p;
}

std::string RequireType(const Json& j) { return json::RequireString(j, "type", 40); }

Json FeatureJson(const services::Feature& f) {
  Json j = {{"id", f.id}, {"type", f.type}, {"anchor_m", {f.anchor_m.x(), f.anchor_m.y(), f.anchor_m.z()}},
            {"stamp", f.stamp_ns}, {"keyframe", f.keyframe ? Json(*f.keyframe) : Json(nullptr)},
            {"codeword", f.codeword ? Json(*f.codeword) : Json(nullptr)}};
  if (!f.descriptor.empty()) j["descriptor"] = f.descriptor;
  return j;
}

// "x,y;x,y;..." [m]
std::vector<Eigen::Vector2d> ParsePolygon(const std::string& text) {
  std::vector<Eigen::Vector2d> out;
  std::stringstream in(text);
  std::string vertex;
  while (std::getline(in, vertex, ';')) {
    double x = 0, y = 0;
    char tail = 0;
    if (std::sscanf(vertex.c_str(), "%lf,%lf%c", &x, &y, &tail) != 2 || !std::isfinite(x) || !std::isfinite(y)) {
      throw Error(ErrorCode::kInvalidArgument, "polygon must be x,y;x,y;x,y in metres", "polygon");
    }
    out.emplace_back(x, y);
    if (out.size() > 10000) throw Error(ErrorCode::kPayloadTooLarge, "at most 10000 polygon vertices", "polygon");
  }
  return out;
}

void ParseBox(const httplib::Request& req, std::optional<Eigen::Vector3d>& lo, std::optional<Eigen::Vector3d>& hi) {
  const auto text = Query(req, "bbox");
  if (!text) return;
  double v[6];
  char tail = 0;
  const int n = std::sscanf(text->c_str(), "%lf,%lf,%lf,%lf,%lf,%lf%c", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5], &tail);
  if (n == 6) {
    lo = Eigen::Vector3d(v[0], v[1], v[2]);
    hi = Eigen::Vector3d(v[3], v[4], v[5]);
  } else if (n == 4) {
    lo = Eigen::Vector3d(v[0], v[1], -1e9);
    hi = Eigen::Vector3d(v[2], v[3], 1e9);
  } else {
    throw Error(ErrorCode::kInvalidArgument, "bbox must be min_x,min_y,min_z,max_x,max_y,max_z (or min_x,min_y,max_x,max_y) in metres",
                "bbox");
  }
  if (!lo->allFinite() || !hi->allFinite()) throw Error(ErrorCode::kInvalidArgument, "bbox must be finite", "bbox");
}

void ParseSphere(const httplib::Request& req, std::optional<Eigen::Vector3d>& near, double& radius) {
  near = QueryPoint3(req, "near");
  if (near) {
    const auto r = OptionalQueryNumber(req, "radius");
    if (!r) throw Error(ErrorCode::kInvalidArgument, "near needs radius (metres)", "radius");
    if (*r < 0 || *r > 1e4) throw Error(ErrorCode::kUnprocessable, "radius must be in [0, 10000] m", "radius");
    radius = *r;
  } else if (req.has_param("radius")) {
    throw Error(ErrorCode::kInvalidArgument, "radius needs near=x,y,z", "near");
  }
}

}  // namespace

services::FeatureBatch ParseFeatureBatch(const Json& body) {
  json::RejectUnknownKeys(body, {"type", "stamp", "features"});
  services::FeatureBatch b;
  b.type = RequireType(body);
  if (body.contains("stamp")) b.stamp_ns = json::AsStampNs(body["stamp"], "stamp");
  const Json& items = json::Require(body, "features");
  if (!items.is_array()) throw Error(ErrorCode::kInvalidArgument, "features must be an array", "features");
  for (std::size_t i = 0; i < items.size(); ++i) {
    const std::string field = "features[" + std::to_string(i) + "]";
    const Json& f = items[i];
    if (!f.is_object()) throw Error(ErrorCode::kInvalidArgument, "a feature is an object", field);
    json::RejectUnknownKeys(f, {"descriptor", "anchor_m", "keyframe"}, field);
    services::FeatureItem item;
    item.descriptor = AsDescriptor(json::Require(f, "descriptor", field), field + ".descriptor");
    item.anchor_m = AsPoint3(json::Require(f, "anchor_m", field), field + ".anchor_m");
    if (f.contains("keyframe") && !f["keyframe"].is_null()) {
      if (!f["keyframe"].is_number_integer()) throw Error(ErrorCode::kInvalidArgument, "keyframe is an id", field + ".keyframe");
      item.keyframe = f["keyframe"].get<std::int64_t>();
    }
    b.features.push_back(std::move(item));
  }
  return b;
}

Json ToJson(const services::FeatureBatchResult& r) {
  return {{"inserted", r.inserted}, {"duplicates", r.duplicates}, {"ids", r.ids}, {"duplicate", r.duplicate}};
}

services::FeatureQuery ParseFeatureQuery(const httplib::Request& req) {
  services::FeatureQuery q;
  if (auto type = QueryString(req, "type", 40)) q.type = *type;
  ParseSphere(req, q.near_m, q.radius_m);
  ParseBox(req, q.box_min_m, q.box_max_m);
  q.since_ns = QueryTime(req, "since");
  q.until_ns = QueryTime(req, "until");
  if (req.has_param("keyframe")) q.keyframe = QueryInteger(req, "keyframe", 0, 0, std::numeric_limits<std::int64_t>::max());
  q.after_id = QueryInteger(req, "after", 0, 0, std::numeric_limits<std::int64_t>::max());
  q.limit = static_cast<int>(QueryInteger(req, "limit", 1000, 1, 10000));
  q.descriptors = QueryTrueFalse(req, "descriptors", true);
  return q;
}

Json ToJson(const services::FeaturePage& page) {
  Json list = Json::array();
  for (const auto& f : page.features) list.push_back(FeatureJson(f));
  Json j = {{"features", list}};
  if (page.next_after) j["next_after"] = *page.next_after;
  return j;
}

services::CodebookRequest ParseCodebookRequest(const Json& body) {
  json::RejectUnknownKeys(body, {"type", "words", "seed"});
  services::CodebookRequest r;
  r.type = RequireType(body);
  r.words = static_cast<int>(json::IntegerOr(body, "words", r.words));
  const std::int64_t seed = json::IntegerOr(body, "seed", 1);
  if (seed < 0) throw Error(ErrorCode::kInvalidArgument, "seed must not be negative", "seed");
  r.seed = static_cast<std::uint64_t>(seed);
  return r;
}

Json ToJson(const services::CodebookView& b, bool centres) {
  Json j = {{"type", b.type}, {"words", b.words}, {"dims", b.dims}, {"seed", b.seed}, {"features", b.features},
            {"created", b.created_ns}};
  if (centres) j["centres"] = b.centres;
  return j;
}

services::BowQuery ParseBowQuery(const httplib::Request& req) {
  services::BowQuery q;
  const auto type = QueryString(req, "type", 40);
  if (!type) throw Error(ErrorCode::kInvalidArgument, "query parameter 'type' is required", "type");
  q.type = *type;
  ParseSphere(req, q.near_m, q.radius_m);
  ParseBox(req, q.box_min_m, q.box_max_m);
  if (auto polygon = Query(req, "polygon")) q.polygon_m = ParsePolygon(*polygon);
  q.since_ns = QueryTime(req, "since");
  q.until_ns = QueryTime(req, "until");
  return q;
}

Json ToJson(const services::BowResult& r) {
  return {{"type", r.type}, {"words", r.words}, {"features", r.features}, {"histogram", r.histogram}};
}

services::ExtractRequest ParseExtractRequest(const Json& body) {
  json::RejectUnknownKeys(body, {"types"});
  services::ExtractRequest r;
  if (body.contains("types")) {
    const Json& types = body["types"];
    if (!types.is_array() || types.size() > 8) throw Error(ErrorCode::kInvalidArgument, "types must be an array of names", "types");
    r.types.clear();
    for (const Json& t : types) {
      if (!t.is_string() || t.get<std::string>().size() > 40) throw Error(ErrorCode::kInvalidArgument, "types must be names", "types");
      r.types.push_back(t.get<std::string>());
    }
  }
  return r;
}

Json ToJson(const services::ExtractResult& r) {
  Json types = Json::array();
  for (const auto& t : r.types) {
    types.push_back({{"type", t.type}, {"extracted", t.extracted}, {"inserted", t.inserted}, {"duplicates", t.duplicates}});
  }
  return {{"keyframe", r.keyframe}, {"points", r.points}, {"types", types}, {"extract_seconds", r.extract_seconds}};
}

Json ToJson(const storage::CodebookJobRequest& r) { return {{"type", r.type}, {"words", r.words}, {"seed", r.seed}}; }

Json ToJson(const storage::CodebookJobResult& r) {
  return {{"type", r.type}, {"words", r.words}, {"dims", r.dims}, {"features", r.features}, {"assigned", r.assigned}};
}

}  // namespace anchordb::api
