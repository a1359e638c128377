#pragma once
// API tokens: random secrets shown once at creation; only their SHA-256 is stored.
#include <string>

#include "storage/store.h"

namespace anchordb::server {

std::string Sha256Hex(const std::string& text);

struct CreatedToken {
  std::string id;
  std::string secret;  // "adb_" + 32 hex digits; never stored
  std::string role;
};

// role: reader | writer | admin (std::invalid_argument otherwise).
CreatedToken CreateToken(storage::Store& store, const std::string& role);

}  // namespace anchordb::server
