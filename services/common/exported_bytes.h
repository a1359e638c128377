#pragma once
// Bytes a service hands out as they are (a layer as PNG/PGM/YAML/raw, a keyframe image): content type, body and
// extra headers the edge passes on (e.g. a layer's geometry for raw arrays).
#include <map>
#include <string>

namespace anchordb::services {

struct ExportedLayer {
  std::string content_type;
  std::string body;
  std::map<std::string, std::string> headers;
};

}  // namespace anchordb::services
