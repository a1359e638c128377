#include "schema/ids.h"

#include <cctype>

#include "schema/error.h"

namespace anchordb::json {

bool IsValidId(std::string_view id) {
  if (id.empty() || id.size() > 64 || id.front() == '.') return false;
  for (char c : id) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.')) return false;
  }
  return true;
}

void CheckId(std::string_view id, const std::string& field) {
  if (!IsValidId(id)) {
    throw Error(ErrorCode::kInvalidArgument, field + ": must be 1-64 characters of [A-Za-z0-9_.-], not starting with '.'", field);
  }
}

}  // namespace anchordb::json
