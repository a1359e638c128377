#include "storage/dialect.h"

namespace anchordb::storage {

std::string PointInBox(Engine engine, const SpatialIndex& index, const BoxBounds& box) {
  const bool three_d = !index.z.empty();
  std::string sql;
  if (engine == Engine::kPostgresql) {
    // box(point, point) takes any two opposite corners; `<@` on point(x, y) is what the GiST index answers.
    sql = "point(" + std::string(index.x) + ", " + std::string(index.y) + ") <@ box(point(" + std::string(box.hi_x) +
          ", " + std::string(box.hi_y) + "), point(" + std::string(box.lo_x) + ", " + std::string(box.lo_y) + "))";
    if (three_d) sql += " AND " + std::string(index.z) + " <= " + std::string(box.hi_z) + " AND " +
                        std::string(index.z) + " >= " + std::string(box.lo_z);
    return sql;
  }
  // The R*Tree stores float bounds that enclose the double coordinates: the row test follows where exactness matters.
  sql = std::string(index.row_key) + " IN (SELECT " + std::string(index.rtree_key) + " FROM " +
        std::string(index.rtree) + " WHERE min_x <= " + std::string(box.hi_x) + " AND min_y <= " +
        std::string(box.hi_y) + " AND max_x >= " + std::string(box.lo_x) + " AND max_y >= " + std::string(box.lo_y);
  if (three_d) sql += " AND min_z <= " + std::string(box.hi_z) + " AND max_z >= " + std::string(box.lo_z);
  return sql + ")";
}

}  // namespace anchordb::storage
