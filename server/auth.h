#pragma once
// API tokens: random secrets shown once at creation; only their SHA-256 is stored. A secret reads
// "adb_<8 hex: the token id>_<32 hex>": the id part (not secret) finds the stored row, then the digests are compared
// in constant time. Secrets made before the id was part of them ("adb_<32 hex>") are matched against every stored
// token, each comparison constant-time and none cut short.
#include <optional>
#include <string>

#include "storage/store.h"

namespace anchordb::server {

std::string Sha256Hex(const std::string& text);

struct CreatedToken {
  std::string id;      // "tok_<8 hex>"
  std::string secret;  // "adb_<8 hex>_<32 hex>"; never stored
  std::string role;
};

// role: reader | writer | admin (std::invalid_argument otherwise). `actor` names who asked (for the audit entry
// written in the same transaction as the token, SPEC §8), e.g. "cli".
CreatedToken CreateToken(storage::Store& store, const std::string& role, const std::string& actor = "cli");

struct AuthenticatedToken {
  std::string id;
  std::string role;
};

// The token a presented secret belongs to, or nullopt. The time taken does not depend on how many leading bytes
// of the secret's digest match a stored one.
std::optional<AuthenticatedToken> Authenticate(storage::Store& store, const std::string& presented_secret);

// Whether two strings are equal, in time that depends on their lengths only (OpenSSL's CRYPTO_memcmp).
bool ConstantTimeEquals(const std::string& a, const std::string& b);

}  // namespace anchordb::server
