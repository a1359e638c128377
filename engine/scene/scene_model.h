#pragma once
// The Articulated Scene Model of one fixed viewpoint (thesis Definition 1, 3.2.3, Algorithm 1): per pixel a
// static background depth with a reliability weight, and the movable and dynamic labels of the latest frame.
// Pure std: images are row-major vectors of width x height.
#include <cstdint>
#include <span>
#include <vector>

namespace anchordb::engine {

// How the tracker's dynamic regions D_t enter Algorithm 1 (thesis 3.2.3).
enum class DynamicMode {
  kExcludeFromInput,     // default: F'_t = F_t \ D_t; excluded pixels update nothing and are labelled dynamic
  kSubtractFromMovable,  // eqs. 3.4-3.5: run on F_t, then O'_t = O_t \ D_t and D'_t = O_t ∩ D_t
};

struct SceneModelParams {
  double beta = 0.03;  // depth-proportional noise factor: theta(d) = beta * d
  // Input filter for structured-light depth (issue 13): a pixel at a depth discontinuity (DepthEdgeMask with
  // jump fraction beta) counts as not measured. There a Kinect-like sensor reports flying (mixed) depths between
  // the two surfaces and edges that wobble by about a pixel from frame to frame (Nguyen et al. 2012); either would
  // put a static pixel nearer than its background by more than theta and label it movable. Jumps smaller than
  // theta cannot do that, so only they are kept. Costs the outermost pixel ring of every object its label. Off by
  // default for now: the ring changes the exact pixel counts the service tests assert on 64 x 48 step images, and
  // at that resolution a steep continuous plane changes by more than theta per pixel (at 640 x 480, fx 525, only
  // beyond ~86 deg incidence, where a Kinect measures nothing). The single-view evaluation turns it on.
  bool drop_depth_edges = false;
  DynamicMode dynamic_mode = DynamicMode::kExcludeFromInput;
};

struct SceneModelState {
  int width = 0;
  int height = 0;
  std::vector<float> background_m;     // s_t per pixel [m]; 0 = nothing known yet (s_0 = 0)
  std::vector<float> weight;           // w per pixel, reliability of the background (1 after a reset)
  std::vector<std::uint8_t> movable;   // O'_t of the latest frame that measured the pixel (0/1)
  std::vector<std::uint8_t> dynamic;   // D'_t of the latest frame (0/1)
  std::int64_t frames = 0;             // frames applied
};

SceneModelState NewSceneModel(int width, int height);

struct FrameCounts {
  std::size_t supported = 0;   // |f - s| < theta: running mean updated (line 4)
  std::size_t reset = 0;       // f farther than s: background reset to f, weight 1 (line 8)
  std::size_t movable = 0;     // f nearer than s: movable (line 11), after the dynamic rule
  std::size_t dynamic = 0;
  std::size_t no_depth = 0;    // f = 0, or dropped as a depth edge: nothing updated
};

// 1 where a measured pixel's depth differs from a measured 4-neighbour's by more than jump_fraction times the
// nearer of the two (both pixels of such a pair are marked), 0 elsewhere. `depth` is row-major width x height, any
// units, 0 = no measurement (never marked, never a partner). O(pixels).
std::vector<std::uint8_t> DepthEdgeMask(std::span<const std::uint16_t> depth, int width, int height,
                                        double jump_fraction);

// Applies one frame. `depth` holds raw sensor units (e.g. mm) with `units_per_m` of them per metre (1000 for
// ROS 16UC1, 5000 for TUM); 0 = no measurement. `dynamic_mask` (0/1 per pixel) may be empty. Sizes must match the
// state (checked by the caller). With params.drop_depth_edges the pixels of DepthEdgeMask(depth, beta) update
// nothing and keep their labels, as pixels without depth do.
FrameCounts ApplyFrame(SceneModelState& state, std::span<const std::uint16_t> depth, double units_per_m,
                       std::span<const std::uint8_t> dynamic_mask, const SceneModelParams& params);

// The noise-cleaning heuristic of 3.5.1: a movable pixel survives when at least `min_fraction` of the other
// pixels in its window x window neighbourhood are movable (pixels outside the image count as not movable).
// Computed with an integral image, O(pixels) whatever the window.
std::vector<std::uint8_t> CleanMovable(const std::vector<std::uint8_t>& movable, int width, int height, int window = 15,
                                       double min_fraction = 0.25);

}  // namespace anchordb::engine
