# Writes a C++ source holding api/openapi.json. Inputs: IN, OUT.
file(READ "${IN}" text)
# The document is one literal longer than the 65536 characters the standard guarantees; GCC and clang accept it, and
# clang's -Woverlength-strings (which -Wpedantic enables there) is silenced for this literal alone.
file(WRITE "${OUT}.tmp" "#include \"api/http_api.h\"\n#if defined(__clang__)\n#pragma clang diagnostic push\n#pragma clang diagnostic ignored \"-Woverlength-strings\"\n#endif\nnamespace anchordb::api {\nconst std::string& HttpApi::OpenApiDocument() {\n  static const std::string kDocument = R\"anchordb_openapi(${text})anchordb_openapi\";\n  return kDocument;\n}\n}  // namespace anchordb::api\n#if defined(__clang__)\n#pragma clang diagnostic pop\n#endif\n")
execute_process(COMMAND ${CMAKE_COMMAND} -E copy_if_different "${OUT}.tmp" "${OUT}")
