#include "services/grid/grid_types.h"

#include "storage/layer_codec_json.h"

namespace anchordb::services {

std::string LayerMetaDocument(const LayerMeta& meta) {
  return std::visit([](const auto& m) { return storage::MetaToJson(m).dump(); }, meta);
}

}  // namespace anchordb::services
