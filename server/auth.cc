#include "server/auth.h"

#include <openssl/evp.h>
#include <openssl/rand.h>

#include <chrono>
#include <stdexcept>

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
}  // namespace

std::string Sha256Hex(const std::string& text) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int n = 0;
  EVP_Digest(text.data(), text.size(), digest, &n, EVP_sha256(), nullptr);
  return Hex(digest, n);
}

CreatedToken CreateToken(storage::Store& store, const std::string& role) {
  if (role != "reader" && role != "writer" && role != "admin") {
    throw std::invalid_argument("role must be reader, writer or admin");
  }
  CreatedToken t{"tok_" + RandomHex(4), "adb_" + RandomHex(16), role};
  storage::TokenRecord record{t.id, Sha256Hex(t.secret), role,
                              std::chrono::duration_cast<std::chrono::nanoseconds>(
                                  std::chrono::system_clock::now().time_since_epoch()).count()};
  store.Write([&](storage::Connection& c) { storage::InsertToken(c, record); });
  return t;
}

}  // namespace anchordb::server
