// Pieces both synthetic scene generators (two_view_scene.cc, multiview_scene.cc) build on: a portable random
// stream, a seed mixer and a box yawed about the vertical z axis. Internal to src/madsfm/synthetic/ (not installed
// as an API); the generators' outputs depend on every bit of these, so any change alters every synthetic set.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>

namespace madsfm {
namespace synthetic {

// SplitMix64's output function: decorrelates consecutive seeds.
inline uint64_t SplitMix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

// Portable sampling on top of std::mt19937_64 (the std:: distributions differ between standard libraries).
class Rng {
 public:
  explicit Rng(uint64_t seed) : engine_(seed) {}
  double Uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }  // [0, 1)
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
  double LogUniform(double lo, double hi) { return std::exp(Uniform(std::log(lo), std::log(hi))); }
  int UniformInt(int lo, int hi) {  // inclusive
    const int v = lo + static_cast<int>(Uniform() * (hi - lo + 1));
    return std::min(v, hi);
  }
  double Normal() {  // Box-Muller
    constexpr double kTwoPi = 6.28318530717958647692;
    const double u1 = 1.0 - Uniform();  // (0, 1]
    const double u2 = Uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(kTwoPi * u2);
  }
  double TruncatedNormal(double limit) {
    for (int i = 0; i < 100; ++i) {
      const double v = Normal();
      if (std::abs(v) <= limit) return v;
    }
    return 0.0;
  }

 private:
  std::mt19937_64 engine_;
};

// An axis-aligned box yawed about the vertical z axis; its six faces are surfaces first_surface + 0..5
// (-x, +x, -y, +y, -z, +z).
struct Box {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d half = Eigen::Vector3d::Ones();
  double cos_yaw = 1.0, sin_yaw = 0.0;
  int first_surface = 0;
};

// A box of the given full size and yaw whose faces take the next six surface ids of *num_surfaces.
inline Box MakeBox(const Eigen::Vector3d& center, const Eigen::Vector3d& size, double yaw, int* num_surfaces) {
  Box b;
  b.center = center;
  b.half = 0.5 * size;
  b.cos_yaw = std::cos(yaw);
  b.sin_yaw = std::sin(yaw);
  b.first_surface = *num_surfaces;
  *num_surfaces += 6;
  return b;
}

// World direction / offset from the box centre -> the box's frame, and back.
inline Eigen::Vector3d ToLocal(const Box& b, const Eigen::Vector3d& v) {
  return Eigen::Vector3d(b.cos_yaw * v.x() + b.sin_yaw * v.y(), -b.sin_yaw * v.x() + b.cos_yaw * v.y(), v.z());
}
inline Eigen::Vector3d ToWorld(const Box& b, const Eigen::Vector3d& v) {
  return Eigen::Vector3d(b.cos_yaw * v.x() - b.sin_yaw * v.y(), b.sin_yaw * v.x() + b.cos_yaw * v.y(), v.z());
}

}  // namespace synthetic
}  // namespace madsfm
