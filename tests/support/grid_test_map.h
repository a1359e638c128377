#pragma once
// A small map_server map for grid service tests: 40 x 30 cells of 0.1 m, origin (-1, -1), free except a wall
// along x = 20 (cells y 1..15) and an unknown block (x 30..38, y 20..28).
#include <string>

namespace anchordb::testing {

inline std::string GridTestYaml() {
  return "image: map.pgm\nresolution: 0.1\norigin: [-1.0, -1.0, 0.0]\nnegate: 0\noccupied_thresh: 0.65\n"
         "free_thresh: 0.196\n";
}

// PGM (P5) of the map; image row 0 is the top (iy = 29).
inline std::string GridTestPgm() {
  const int w = 40, h = 30;
  std::string pgm = "P5\n" + std::to_string(w) + " " + std::to_string(h) + "\n255\n";
  for (int row = 0; row < h; ++row) {
    const int iy = h - 1 - row;
    for (int ix = 0; ix < w; ++ix) {
      unsigned char v = 254;
      if (ix == 20 && iy >= 1 && iy <= 15) v = 0;
      if (ix >= 30 && ix <= 38 && iy >= 20 && iy <= 28) v = 205;
      pgm.push_back(static_cast<char>(v));
    }
  }
  return pgm;
}

}  // namespace anchordb::testing
