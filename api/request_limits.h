#pragma once
// Limits on the length of every string and array a request may carry (SPEC §8: sizes are validated, bad input
// changes nothing), in one place. A string over its limit is 400 and an array over its limit 413, both naming the
// field; api/openapi.json states the same figures as maxLength / maxItems. Limits an operator tunes are settings
// instead (--help): polygons per request and vertices per polygon (max_polygons, max_polygon_vertices), furniture
// pieces per graph (grounding_max_furniture), description text (grounding_max_text_length), body bytes
// (max_body_bytes), page sizes.
#include <cstddef>
#include <string>

#include "schema/error.h"
#include "schema/json_io.h"

namespace anchordb::api::limits {

inline constexpr std::size_t kIdLength = 64;              // ids of maps, layers, agents, pieces; actor= / action=
inline constexpr std::size_t kNameLength = 256;           // display names of maps
inline constexpr std::size_t kLabelLength = 256;          // labels of instances, events, label layers; label=
inline constexpr std::size_t kWordLength = 32;            // enumerated words (kind, op, source, modes, ...)
inline constexpr std::size_t kBackupLabelLength = 64;     // a backup's label (part of its file name)
inline constexpr std::size_t kDescriptionWordLength = 64; // located / relation / reference of a description
inline constexpr std::size_t kCategoryWordLength = 64;    // a furniture category word
inline constexpr std::size_t kCategoriesPerPiece = 64;    // category probabilities of one furniture piece
inline constexpr std::size_t kFusedOperands = 16;         // operands of a fused layer
inline constexpr std::size_t kQueryValueLength = 1024;    // any query parameter value
inline constexpr std::size_t kQueryParameters = 64;       // query parameters of one request

// kPayloadTooLarge naming `field` when the array `v` has more than `max_items` elements.
inline void CheckItems(const json::Json& v, std::size_t max_items, const std::string& field) {
  if (v.size() > max_items) {
    throw Error(ErrorCode::kPayloadTooLarge, field + ": more than " + std::to_string(max_items) + " items", field);
  }
}

// kInvalidArgument naming `field` when `text` is longer than `max_length` bytes.
inline void CheckLength(const std::string& text, std::size_t max_length, const std::string& field) {
  if (text.size() > max_length) {
    throw Error(ErrorCode::kInvalidArgument, field + ": longer than " + std::to_string(max_length) + " bytes", field);
  }
}

}  // namespace anchordb::api::limits
