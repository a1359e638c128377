#pragma once
// Seeded, platform-independent random draws for the evaluation suites (no unseeded randomness anywhere).
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

namespace anchordb::eval {

class SeededRng {
 public:
  explicit SeededRng(std::uint64_t seed) : engine_(seed) {}
  double Uniform(double lo, double hi) { return lo + (hi - lo) * static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  int Below(int n) { return static_cast<int>(engine_() % static_cast<std::uint64_t>(n)); }
  bool Chance(double p) { return Uniform(0.0, 1.0) < p; }
  template <typename T>
  void Shuffle(std::vector<T>& v) {
    for (std::size_t i = v.size(); i > 1; --i) std::swap(v[i - 1], v[static_cast<std::size_t>(Below(static_cast<int>(i)))]);
  }

 private:
  std::mt19937_64 engine_;
};

}  // namespace anchordb::eval
