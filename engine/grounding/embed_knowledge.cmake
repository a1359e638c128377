# Writes a C++ source holding engine/grounding/categories.json and frame_prior.json. Inputs: IN_DIR, OUT.
file(READ "${IN_DIR}/categories.json" categories)
file(READ "${IN_DIR}/frame_prior.json" prior)
file(WRITE "${OUT}.tmp" "#include \"engine/grounding/knowledge.h\"\nnamespace anchordb::engine::grounding {\nstd::string_view DefaultCategoriesJson() {\n  static const char kText[] = R\"anchordb_json(${categories})anchordb_json\";\n  return {kText, sizeof(kText) - 1};\n}\nstd::string_view DefaultFramePriorJson() {\n  static const char kText[] = R\"anchordb_json(${prior})anchordb_json\";\n  return {kText, sizeof(kText) - 1};\n}\n}  // namespace anchordb::engine::grounding\n")
execute_process(COMMAND ${CMAKE_COMMAND} -E copy_if_different "${OUT}.tmp" "${OUT}")
