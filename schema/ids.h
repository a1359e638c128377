#pragma once
// Identifiers of maps, layers, agents, classifiers and shape models: 1-64 characters of [A-Za-z0-9_.-], not starting
// with '.'. The rule has no JSON in it: services check ids with it without reaching the JSON readers
// (schema/json_io.h, which uses it for ids inside request bodies). Declared in namespace json, where its callers
// have always found it.
#include <string>
#include <string_view>

namespace anchordb::json {

bool IsValidId(std::string_view id);
// Error(kInvalidArgument, "<field>: must be ...", field) unless IsValidId(id).
void CheckId(std::string_view id, const std::string& field);

}  // namespace anchordb::json
