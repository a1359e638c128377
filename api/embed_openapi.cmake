# Writes a C++ source holding api/openapi.json. Inputs: IN, OUT.
file(READ "${IN}" text)
file(WRITE "${OUT}.tmp" "#include \"api/http_api.h\"\nnamespace anchordb::api {\nconst std::string& HttpApi::OpenApiDocument() {\n  static const std::string kDocument = R\"anchordb_openapi(${text})anchordb_openapi\";\n  return kDocument;\n}\n}  // namespace anchordb::api\n")
execute_process(COMMAND ${CMAKE_COMMAND} -E copy_if_different "${OUT}.tmp" "${OUT}")
