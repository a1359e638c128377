#pragma once
// The operator console (SPEC §4.10) at /ui/: the static files of clients/web compiled into the binary
// (api/embed_console.cmake), served without a token (they hold no data; the page calls the API with the token its
// user types, and shows only the edits that token's role may make).
#include <string_view>
#include <vector>

#include "api/router.h"

namespace anchordb::api {

struct ConsoleFile {
  std::string_view name;  // "index.html"
  std::string_view bytes;
};
// Generated at build time from clients/web.
const std::vector<ConsoleFile>& ConsoleFiles();

void RegisterConsoleRoutes(Router& router);

}  // namespace anchordb::api
