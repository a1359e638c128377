#include "server/auth.h"

#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <openssl/rand.h>

#include <stdexcept>

#include "schema/clock.h"
#include "schema/json_io.h"
#include "storage/audit_repository.h"
#include "storage/repositories.h"

namespace anchordb::server {
namespace {
std::string Hex(const unsigned char* bytes, std::size_t n) {
  static const char* kDigits = "0123456789abcdef";
  std::string out;
  for (std::size_t i = 0; i < n; ++i) out += kDigits[bytes[i] >> 4], out += kDigits[bytes[i] & 15];
  return out;
}

std::string RandomHex(std::size_t bytes) {
  std::vector<unsigned char> buf(bytes);
  if (RAND_bytes(buf.data(), static_cast<int>(bytes)) != 1) throw std::runtime_error("no system randomness for tokens");
  return Hex(buf.data(), bytes);
}

constexpr std::size_t kIdHexDigits = 8;
constexpr std::size_t kSecretHexDigits = 32;

bool IsLowerHex(const std::string& s, std::size_t from, std::size_t n) {
  for (std::size_t i = from; i < from + n; ++i) {
    const char c = s[i];
    if (!((c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'))) return false;
  }
  return true;
}

// The token id named by a secret "adb_<8 hex>_<32 hex>", or nullopt for any other form.
std::optional<std::string> TokenIdOf(const std::string& secret) {
  if (secret.size() != 4 + kIdHexDigits + 1 + kSecretHexDigits || secret.rfind("adb_", 0) != 0 ||
      secret[4 + kIdHexDigits] != '_' || !IsLowerHex(secret, 4, kIdHexDigits) ||
      !IsLowerHex(secret, 5 + kIdHexDigits, kSecretHexDigits)) {
    return std::nullopt;
  }
  return "tok_" + secret.substr(4, kIdHexDigits);
}

}  // namespace

std::string Sha256Hex(const std::string& text) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int n = 0;
  EVP_Digest(text.data(), text.size(), digest, &n, EVP_sha256(), nullptr);
  return Hex(digest, n);
}

bool ConstantTimeEquals(const std::string& a, const std::string& b) {
  return a.size() == b.size() && CRYPTO_memcmp(a.data(), b.data(), a.size()) == 0;
}

CreatedToken CreateToken(storage::Store& store, const std::string& role, const std::string& actor) {
  if (role != "reader" && role != "writer" && role != "admin") {
    throw std::invalid_argument("role must be reader, writer or admin");
  }
  const std::string id_hex = RandomHex(kIdHexDigits / 2);
  CreatedToken t{"tok_" + id_hex, "adb_" + id_hex + "_" + RandomHex(kSecretHexDigits / 2), role};
  storage::TokenRecord record{t.id, Sha256Hex(t.secret), role, SystemClock::Instance().NowNs()};
  storage::AuditRecord audit;
  audit.time_ns = record.created_ns, audit.actor = actor, audit.action = "token.create", audit.resource = t.id;
  audit.after_json = json::Json{{"id", t.id}, {"role", role}, {"created_ns", record.created_ns}}.dump();
  store.Write([&](storage::Connection& c) {
    storage::InsertToken(c, record);  // a (2^-32 likely) repeated id fails on the primary key: nothing is written
    storage::InsertAuditRecord(c, audit);
  });
  return t;
}

std::optional<AuthenticatedToken> Authenticate(storage::Store& store, const std::string& presented_secret) {
  const std::string digest = Sha256Hex(presented_secret);
  if (const auto id = TokenIdOf(presented_secret)) {
    const auto record = store.Read([&](storage::Connection& c) { return storage::FindTokenById(c, *id); });
    if (!record || !ConstantTimeEquals(digest, record->sha256_hex)) return std::nullopt;
    return AuthenticatedToken{record->id, record->role};
  }
  // A secret of the earlier form: compared with every stored digest, never stopping at the first match.
  const auto records = store.Read([](storage::Connection& c) { return storage::ListTokens(c); });
  std::optional<AuthenticatedToken> found;
  for (const auto& r : records) {
    if (ConstantTimeEquals(digest, r.sha256_hex) && !found) found = AuthenticatedToken{r.id, r.role};
  }
  return found;
}

}  // namespace anchordb::server
