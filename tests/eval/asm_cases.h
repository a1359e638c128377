#pragma once
// The single-viewpoint evaluation of thesis 3.5.1 (appendix A cases A0-A4), rebuilt with the synthetic renderer:
// a scene is observed from viewpoint A for some frames, something changes, and it is observed again; the movable
// layer is then scored pixel by pixel against the renderer's object ids (Table 3.1).
#include <string>
#include <vector>

#include "sim/apartment.h"
#include "tests/support/pixel_metrics.h"

namespace anchordb::eval {

enum class AsmCase {
  kA0,  // an object is moved (20 cm along the surface)
  kA1,  // an elongated object is moved only slightly (4 cm) along its main axis
  kA2,  // a very thin object (1 cm) is moved
  kA3,  // a tall object is placed in front of an area with no measurement so far
  kA4,  // two movable objects are placed close together
};
const char* AsmCaseName(AsmCase c);

struct AsmResult {
  testing::PixelCounts raw;          // movable layer as computed, every pixel counted
  testing::PixelCounts cleaned;      // after the 15 x 15 / 25 % noise cleaning
  testing::PixelCounts cleaned_zone; // cleaned, transition zone (2 px either side of the truth's boundary) ignored
  std::size_t truth_pixels = 0;
};

struct AsmOptions {
  int frames_before = 10;
  int frames_after = 10;
  int zone_radius_px = 2;
  double beta = 0.03;
  bool drop_depth_edges = true;  // SceneModelParams::drop_depth_edges
};

AsmResult RunAsmCase(sim::Setting setting, AsmCase c, std::uint64_t seed, const AsmOptions& options = {});

}  // namespace anchordb::eval
