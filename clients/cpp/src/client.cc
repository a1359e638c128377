// anchordb_client: the typed calls (include/anchordb/client.h) as HTTP requests with cpp-httplib.
#include "anchordb/client.h"

#include <httplib.h>

#include <chrono>
#include <thread>

namespace anchordb::client {
namespace {

std::string Escape(const std::string& s) {  // one path segment or query value
  static const char* kHex = "0123456789ABCDEF";
  std::string out;
  for (unsigned char c : s) {
    if (std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == '~') out += static_cast<char>(c);
    else out += '%', out += kHex[c >> 4], out += kHex[c & 15];
  }
  return out;
}

std::string MapPath(const std::string& map) { return "/v1/maps/" + Escape(map); }

template <typename T>
std::optional<T> Opt(const Json& j, const char* key) {
  if (!j.contains(key) || j[key].is_null()) return std::nullopt;
  return j[key].get<T>();
}

std::array<double, 3> Vec3(const Json& j) {
  std::array<double, 3> v{0, 0, 0};
  if (j.is_array()) for (std::size_t i = 0; i < 3 && i < j.size(); ++i) v[i] = j[i].get<double>();
  return v;
}

MapInfo ToMap(const Json& j) { return {j.value("id", ""), j.value("name", ""), j.value("created_ns", std::int64_t{0})}; }

Event ToEvent(const Json& j) {
  Event e;
  e.id = j.at("id").get<std::int64_t>();
  e.type = j.value("type", "");
  e.detection = j.value("detection", "");
  e.stamp_ns = j.value("stamp_ns", std::int64_t{0});
  e.instance = Opt<std::int64_t>(j, "instance");
  e.label = Opt<std::string>(j, "label");
  e.explanation = j.value("explanation", "");
  e.raw = j;
  return e;
}

Instance ToInstance(const Json& j) {
  Instance i;
  i.id = j.at("id").get<std::int64_t>();
  i.kind = j.value("kind", "");
  i.status = j.value("status", "");
  i.labels = j.value("labels", Json::object());
  i.label_locked = j.value("label_locked", false);
  i.pinned = j.value("pinned", false);
  i.position_m = Vec3(j.value("position_m", Json::array()));
  i.last_seen_ns = j.value("last_seen_ns", std::int64_t{0});
  i.raw = j;
  return i;
}

Job ToJob(const Json& j) {
  Job out;
  out.id = j.contains("id") ? j["id"].get<std::int64_t>() : j.at("job").get<std::int64_t>();
  out.kind = j.value("kind", "");
  out.status = j.value("status", "");
  out.stage = j.value("stage", "");
  out.progress = j.value("progress", 0.0);
  out.request = j.value("request", Json());
  out.result = j.value("result", Json());
  out.error = Opt<std::string>(j, "error");
  return out;
}

}  // namespace

struct Client::Impl {
  Impl(const std::string& host, int port, std::string t, double timeout_s) : http(host, port), token(std::move(t)) {
    const auto s = static_cast<time_t>(timeout_s);
    const auto us = static_cast<time_t>((timeout_s - static_cast<double>(s)) * 1e6);
    http.set_read_timeout(s, us);
    http.set_write_timeout(s, us);
    http.set_connection_timeout(s, us);
    http.set_keep_alive(true);
  }

  httplib::Headers Headers() const {
    httplib::Headers h;
    if (!token.empty()) h.emplace("Authorization", "Bearer " + token);
    return h;
  }

  // Sends one request; returns the body of a 2xx answer, throws otherwise.
  std::string Send(const std::string& method, const std::string& path, const std::string& body,
                   const std::string& content_type) {
    const auto h = Headers();
    httplib::Result r = method == "GET"      ? http.Get(path.c_str(), h)
                        : method == "DELETE" ? http.Delete(path.c_str(), h)
                        : method == "PUT"    ? http.Put(path.c_str(), h, body, content_type.c_str())
                                             : http.Post(path.c_str(), h, body, content_type.c_str());
    return Answer(r, method, path);
  }

  // A multipart/form-data request (PUT or POST) with `items` as its parts.
  std::string SendParts(const std::string& method, const std::string& path, const httplib::MultipartFormDataItems& items) {
    const auto h = Headers();
    httplib::Result r = method == "PUT" ? http.Put(path.c_str(), h, items) : http.Post(path.c_str(), h, items);
    return Answer(r, method, path);
  }

  // The body of a 2xx answer; TransportError without an answer, ApiError (the server's error document) otherwise.
  static std::string Answer(httplib::Result& r, const std::string& method, const std::string& path) {
    if (!r) throw TransportError(method + " " + path + ": " + httplib::to_string(r.error()));
    if (r->status < 200 || r->status >= 300) {
      const Json doc = Json::parse(r->body, nullptr, false);
      const Json e = doc.is_object() && doc.contains("error") ? doc["error"] : Json::object();
      throw ApiError(r->status, e.value("code", "http_" + std::to_string(r->status)),
                     e.value("message", r->body.substr(0, 200)),
                     e.contains("field") && e["field"].is_string() ? e["field"].get<std::string>() : "");
    }
    return r->body;
  }

  Json SendJson(const std::string& method, const std::string& path, const Json& body) {
    const std::string text = Send(method, path, body.is_null() ? "" : body.dump(), "application/json");
    return text.empty() ? Json() : Json::parse(text);
  }

  httplib::Client http;
  std::string token;
};

Client::Client(std::string host, int port, std::string token, double timeout_s)
    : impl_(std::make_unique<Impl>(host, port, std::move(token), timeout_s)) {}
Client::~Client() = default;

Json Client::Request(const std::string& method, const std::string& path, const Json& body) {
  return impl_->SendJson(method, path, body.is_null() && (method == "POST" || method == "PUT") ? Json::object() : body);
}

MapInfo Client::CreateMap(const std::string& id, const std::string& name) {
  return ToMap(Request("POST", "/v1/maps", {{"id", id}, {"name", name.empty() ? id : name}}));
}

std::vector<MapInfo> Client::ListMaps() {
  std::vector<MapInfo> out;
  for (const Json& m : Request("GET", "/v1/maps?limit=1000").value("maps", Json::array())) out.push_back(ToMap(m));
  return out;
}

MapInfo Client::GetMap(const std::string& id) { return ToMap(Request("GET", MapPath(id))); }
void Client::DeleteMap(const std::string& id) { Request("DELETE", MapPath(id)); }

Json Client::ImportLayer(const std::string& map, const std::string& layer, const std::string& yaml_text,
                         const std::string& image_bytes) {
  const bool png = image_bytes.rfind("\x89PNG", 0) == 0;
  httplib::MultipartFormDataItems items = {
      {"yaml", yaml_text, layer + ".yaml", "application/yaml"},
      {"image", image_bytes, layer + (png ? ".png" : ".pgm"), png ? "image/png" : "image/x-portable-graymap"}};
  return Json::parse(impl_->SendParts("PUT", MapPath(map) + "/layers/" + Escape(layer), items));
}

Json Client::CreateLayer(const std::string& map, const std::string& layer, const Json& spec) {
  return Request("PUT", MapPath(map) + "/layers/" + Escape(layer), spec);
}

std::string Client::ExportLayer(const std::string& map, const std::string& layer, const std::string& format) {
  return impl_->Send("GET", MapPath(map) + "/layers/" + Escape(layer) + "?format=" + Escape(format), "", "");
}

Json Client::ListLayers(const std::string& map) { return Request("GET", MapPath(map) + "/layers"); }

Scene Client::OpenScene(const std::string& map, const Camera& c, const Pose& pose, bool merge, const Json& params,
                        std::optional<std::int64_t> stamp_ns) {
  Json body = {{"camera", {{"width", c.width}, {"height", c.height}, {"fx", c.fx}, {"fy", c.fy}, {"cx", c.cx}, {"cy", c.cy}}},
               {"pose", {{"position", pose.position_m}, {"orientation", pose.orientation}}},
               {"merge", merge}};
  if (!params.is_null()) body["params"] = params;
  if (stamp_ns) body["stamp"] = *stamp_ns;
  const Json r = Request("POST", MapPath(map) + "/scenes", body);
  return {r.at("id").get<std::int64_t>(), r.value("merge", Json()), r};
}

FrameResult Client::PostDepthFrame(const std::string& map, std::int64_t scene, const std::uint16_t* depth_mm, int width,
                                   int height, std::optional<std::int64_t> stamp_ns, const std::string& dynamic_png) {
  if (!depth_mm || width <= 0 || height <= 0) throw std::invalid_argument("PostDepthFrame: no depth buffer");
  // Raw little-endian uint16, row-major (SPEC §1); written byte by byte so that the host's byte order does not matter.
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  std::string body(2 * n, '\0');
  for (std::size_t i = 0; i < n; ++i) {
    body[2 * i] = static_cast<char>(depth_mm[i] & 0xff);
    body[2 * i + 1] = static_cast<char>(depth_mm[i] >> 8);
  }
  std::string path = MapPath(map) + "/scenes/" + std::to_string(scene) + "/frames";
  if (stamp_ns) path += "?stamp=" + std::to_string(*stamp_ns);
  const Json r = Json::parse(dynamic_png.empty()
                                 ? impl_->Send("POST", path, body, "application/octet-stream")
                                 : impl_->SendParts("POST", path, {{"depth", body, "depth.raw", "application/octet-stream"},
                                                                   {"dynamic", dynamic_png, "dynamic.png", "image/png"}}));
  return {r.value("frames", std::int64_t{0}), Opt<std::int64_t>(r, "keyframe"), r};
}

Json Client::CloseScene(const std::string& map, std::int64_t scene, bool wait_for_analysis) {
  return Request("POST", MapPath(map) + "/scenes/" + std::to_string(scene) + ":close" +
                             (wait_for_analysis ? "?wait_for_analysis=true" : ""), Json::object());
}

Json Client::GetScene(const std::string& map, std::int64_t scene) {
  return Request("GET", MapPath(map) + "/scenes/" + std::to_string(scene));
}

std::vector<Event> Client::Events(const std::string& map, const EventQuery& q) {
  std::string path = MapPath(map) + "/events?limit=" + std::to_string(q.limit) + "&after=" + std::to_string(q.after);
  if (q.since_ns) path += "&since=" + std::to_string(*q.since_ns);
  if (q.until_ns) path += "&until=" + std::to_string(*q.until_ns);
  if (q.instance) path += "&instance=" + std::to_string(*q.instance);
  if (q.type) path += "&type=" + Escape(*q.type);
  std::vector<Event> out;
  for (const Json& e : Request("GET", path).value("events", Json::array())) out.push_back(ToEvent(e));
  return out;
}

std::vector<Instance> Client::Instances(const std::string& map, const std::string& label, const std::string& kind) {
  std::string path = MapPath(map) + "/instances?limit=1000";
  if (!label.empty()) path += "&label=" + Escape(label);
  if (!kind.empty()) path += "&kind=" + Escape(kind);
  std::vector<Instance> out;
  for (const Json& i : Request("GET", path).value("instances", Json::array())) out.push_back(ToInstance(i));
  return out;
}

Instance Client::GetInstance(const std::string& map, std::int64_t id) {
  return ToInstance(Request("GET", MapPath(map) + "/instances/" + std::to_string(id)));
}

Json Client::LabelInstance(const std::string& map, std::int64_t id, const std::string& label, bool from_operator) {
  return Request("POST", MapPath(map) + "/instances/" + std::to_string(id) + ":label",
                 {{"label", label}, {"source", from_operator ? "operator" : "dialog"}});
}

WhereAnswer Client::Where(const std::string& map, const std::string& label) {
  const Json r = Request("GET", MapPath(map) + "/where?label=" + Escape(label));
  WhereAnswer a;
  a.present = r.value("present", false);
  a.instance = Opt<std::int64_t>(r, "instance");
  a.position_m = Vec3(r.value("position_m", Json::array()));
  a.sentence = r.value("sentence", "");
  for (const Json& k : r.value("evidence", Json::array())) a.evidence_keyframes.push_back(k.at("keyframe").get<std::int64_t>());
  a.raw = r;
  return a;
}

Json Client::CreateFurnitureGraph(const std::string& map, const Json& body) {
  return Request("POST", MapPath(map) + "/furniture-graphs", body);
}

Json Client::GroundDescription(const std::string& map, std::int64_t graph, const std::string& text) {
  return Request("POST", MapPath(map) + "/furniture-graphs/" + std::to_string(graph) + "/descriptions", {{"text", text}});
}

Json Client::Hypotheses(const std::string& map, std::int64_t graph, int limit) {
  return Request("GET", MapPath(map) + "/furniture-graphs/" + std::to_string(graph) + "/hypotheses?limit=" + std::to_string(limit));
}

Json Client::Describe(const std::string& map, std::int64_t graph, const std::string& located, const std::string& reference) {
  return Request("POST", MapPath(map) + "/furniture-graphs/" + std::to_string(graph) + ":describe",
                 {{"located", located}, {"reference", reference}});
}

Job Client::Forget(const std::string& map, const Json& policy, bool dry_run) {
  return ToJob(Request("POST", MapPath(map) + ":forget", {{"policy", policy}, {"dry_run", dry_run}}));
}

Job Client::Backup(const std::string& label) {
  return ToJob(Request("POST", "/v1/backups", label.empty() ? Json::object() : Json{{"label", label}}));
}

Job Client::GetJob(std::int64_t id) { return ToJob(Request("GET", "/v1/jobs/" + std::to_string(id))); }

Job Client::WaitJob(std::int64_t id, const std::function<void(const Job&)>& on_progress, double timeout_s, double poll_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  for (;;) {
    Job j = GetJob(id);
    if (on_progress) on_progress(j);
    if (j.finished()) return j;
    if (std::chrono::steady_clock::now() >= deadline) throw TransportError("job " + std::to_string(id) + " not finished in time");
    std::this_thread::sleep_for(std::chrono::duration<double>(poll_s));
  }
}

}  // namespace anchordb::client
