#pragma once
// Error kinds shared by every module. api/ maps each kind to one HTTP status in one table
// (HttpStatusFor in api/http_api.cc); everything below api/ only throws or returns these kinds.
#include <stdexcept>
#include <string>

namespace anchordb {

enum class ErrorCode {
  kInvalidJson,           // body is not JSON, or not the JSON shape expected (400)
  kInvalidArgument,       // a field has the wrong type, is missing, not finite, too long (400)
  kUnprocessable,         // well-formed but impossible: non-unit quaternion, negative range (422)
  kNotFound,              // unknown map, layer, agent, token (404)
  kConflict,              // already exists, or another entity depends on it (409)
  kUnauthenticated,       // missing or unknown token (401)
  kForbidden,             // token role too low (403)
  kPayloadTooLarge,       // body or array over its limit (413)
  kUnsupportedMediaType,  // wrong Content-Type for the route (415)
  kOverloaded,            // a bounded queue is full (503)
  kUnavailable,           // storage failed for now (I/O error, out of memory); nothing was written, retry (503)
  kInsufficientStorage,   // the disk is full; nothing was written (507)
  kInternal,              // a bug or an I/O failure (500)
};

// Stable machine-readable name of a code ("invalid_argument", ...), used in JSON error bodies.
const char* ErrorCodeName(ErrorCode code);

// The one exception type that crosses module boundaries. `message` is safe to show to a client;
// `field` names the offending request field (JSON pointer-like "pose.orientation"), or is empty.
class Error : public std::runtime_error {
 public:
  Error(ErrorCode code, std::string message, std::string field = {})
      : std::runtime_error(std::move(message)), code_(code), field_(std::move(field)) {}
  ErrorCode code() const { return code_; }
  const std::string& field() const { return field_; }

 private:
  ErrorCode code_;
  std::string field_;
};

}  // namespace anchordb
