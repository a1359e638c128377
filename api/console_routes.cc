// GET /ui, /ui/ and /ui/{file}: the embedded console files (api/console_routes.h).
#include "api/console_routes.h"

#include <string>

#include "schema/error.h"

namespace anchordb::api {
namespace {

std::string ContentType(std::string_view name) {
  const auto ends = [&](std::string_view suffix) {
    return name.size() >= suffix.size() && name.substr(name.size() - suffix.size()) == suffix;
  };
  if (ends(".html")) return "text/html; charset=utf-8";
  if (ends(".js")) return "text/javascript; charset=utf-8";
  if (ends(".css")) return "text/css; charset=utf-8";
  return "application/octet-stream";
}

Response FileResponse(std::string_view name) {
  for (const ConsoleFile& f : ConsoleFiles()) {
    if (f.name != name) continue;
    Response r{200, ContentType(name), std::string(f.bytes), {}};
    r.headers["Cache-Control"] = "no-cache";
    // Only this server's own scripts, styles and API; no external CDN, no inline script.
    r.headers["Content-Security-Policy"] =
        "default-src 'self'; img-src 'self' blob: data:; style-src 'self'; script-src 'self'; connect-src 'self'";
    r.headers["X-Content-Type-Options"] = "nosniff";
    return r;
  }
  throw Error(ErrorCode::kNotFound, "the console has no file '" + std::string(name) + "'", "file");
}

}  // namespace

void RegisterConsoleRoutes(Router& router) {
  router.Add("GET", "/ui", Role::kPublic, "The operator console (redirects to /ui/)", [](const httplib::Request&, const PathParams&) {
    Response r{301, "text/plain", "see /ui/", {}};
    r.headers["Location"] = "/ui/";
    return r;
  });
  router.Add("GET", "/ui/", Role::kPublic, "The operator console (static page served from the binary)",
             [](const httplib::Request&, const PathParams&) { return FileResponse("index.html"); });
  router.Add("GET", "/ui/{file}", Role::kPublic, "A file of the operator console (its scripts and style sheet)",
             [](const httplib::Request&, const PathParams& p) { return FileResponse(p["file"]); });
}

}  // namespace anchordb::api
