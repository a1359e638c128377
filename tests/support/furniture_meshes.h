#pragma once
// Two small furniture meshes for the shape-model tests, as OBJ text (metres, z up): a table (top and four legs) and
// a cabinet (a box with a plinth), both standing on z = 0.
#include <sstream>
#include <string>

namespace anchordb::testing {

inline void ObjBox(std::ostringstream& out, int& base, double x0, double y0, double z0, double x1, double y1, double z1) {
  for (int i = 0; i < 8; ++i) {
    out << "v " << (i & 1 ? x1 : x0) << " " << (i & 2 ? y1 : y0) << " " << (i & 4 ? z1 : z0) << "\n";
  }
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) out << "f " << base + f[0] << " " << base + f[1] << " " << base + f[2] << " " << base + f[3] << "\n";
  base += 8;
}

inline std::string TableObj() {
  std::ostringstream out;
  int base = 1;
  ObjBox(out, base, -0.6, -0.4, 0.70, 0.6, 0.4, 0.74);
  for (double x : {-0.55, 0.50}) {
    for (double y : {-0.35, 0.30}) ObjBox(out, base, x, y, 0.0, x + 0.05, y + 0.05, 0.70);
  }
  return out.str();
}

inline std::string CabinetObj() {
  std::ostringstream out;
  int base = 1;
  ObjBox(out, base, -0.45, -0.25, 0.08, 0.45, 0.25, 1.3);
  ObjBox(out, base, -0.40, -0.20, 0.0, 0.40, 0.20, 0.08);
  ObjBox(out, base, -0.40, -0.27, 0.60, 0.40, -0.25, 0.64);  // a handle rail
  return out.str();
}

}  // namespace anchordb::testing
