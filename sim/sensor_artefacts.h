#pragma once
// Internal to the renderer: the measurement stage of the structured-light sensor model (SensorModel in
// renderer.h), from the ideal depth the ray caster sees to the 16-bit depth the sensor reports. Random draws are
// functions of the seed and the pixel (SplitMix64-derived streams) except the white noise, which the renderer
// draws from std::mt19937_64(seed) as it always did.
#include <cstdint>
#include <vector>

#include "sim/renderer.h"

namespace anchordb::sim::detail {

// Throws std::invalid_argument naming the field if a SensorModel parameter lies outside its documented range.
void CheckSensorModel(const SensorModel& sensor);

// `ideal_m`: per pixel the noiseless optical z [m] where the sensor can measure (range, incidence and shadow
// passed), 0 where it cannot. `white_normal`: one standard normal per pixel (read only if sensor.noise). Writes
// `depth_mm` (width * height, 0 = no measurement).
void MeasureDepth(const SensorModel& sensor, int width, int height, std::uint64_t seed,
                  const std::vector<double>& ideal_m, const std::vector<double>& white_normal,
                  std::vector<std::uint16_t>& depth_mm);

// The axial noise sigma of Nguyen, Izadi, Lovell (2012) [m] at optical depth z_m [m].
inline double NguyenSigmaM(double z_m) { return 0.0012 + 0.0019 * (z_m - 0.4) * (z_m - 0.4); }

}  // namespace anchordb::sim::detail
