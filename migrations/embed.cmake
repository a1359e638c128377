# Writes a C++ source with every migrations/<engine>/NNNN_*.sql as a string, per engine, in file-name order.
# Inputs: SQL_DIR (the migrations folder), OUT.
set(body "#include \"storage/migrations.h\"\nnamespace anchordb::storage {\n")
foreach(engine sqlite postgresql)
  file(GLOB sql_files "${SQL_DIR}/${engine}/[0-9][0-9][0-9][0-9]_*.sql")
  list(SORT sql_files)
  string(APPEND body "static const std::vector<Migration>& Embedded_${engine}() {\n  static const std::vector<Migration> kMigrations = {\n")
  foreach(f ${sql_files})
    get_filename_component(name "${f}" NAME)
    string(SUBSTRING "${name}" 0 4 number)
    math(EXPR version "${number}")
    file(READ "${f}" sql)
    string(APPEND body "    {${version}, \"${name}\", R\"anchordb_sql(${sql})anchordb_sql\"},\n")
  endforeach()
  string(APPEND body "  };\n  return kMigrations;\n}\n")
endforeach()
string(APPEND body "const std::vector<Migration>& EmbeddedMigrations(Engine engine) {\n"
                   "  return engine == Engine::kPostgresql ? Embedded_postgresql() : Embedded_sqlite();\n}\n"
                   "}  // namespace anchordb::storage\n")
file(WRITE "${OUT}.tmp" "${body}")
execute_process(COMMAND ${CMAKE_COMMAND} -E copy_if_different "${OUT}.tmp" "${OUT}")
