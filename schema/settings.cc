#include "schema/settings.h"

#include <sstream>

namespace anchordb {

std::string FormatBound(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

}  // namespace anchordb
