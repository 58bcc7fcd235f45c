#include "madsfm/io/depth_sampling.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace madsfm {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

inline bool Valid(float v) { return v > 0.0f && v <= FLT_MAX; }  // false for NaN, inf and <= 0

// Precomputed mapping from image pixels to map pixels.
struct Sampler {
  Sampler(const DepthMap& m, int image_width, int image_height)
      : map(m),
        ok(!m.Empty() && image_width > 0 && image_height > 0 &&
           m.data.size() >= static_cast<size_t>(m.width) * static_cast<size_t>(m.height)),
        max_x(image_width - 0.5),
        max_y(image_height - 0.5),
        scale_x(ok ? static_cast<double>(m.width) / image_width : 0.0),
        scale_y(ok ? static_cast<double>(m.height) / image_height : 0.0),
        max_u(m.width - 1.0),
        max_v(m.height - 1.0) {}

  double operator()(double x, double y) const {
    // Negated comparisons so that NaN coordinates are rejected too.
    if (!ok || !(x >= -0.5 && x <= max_x && y >= -0.5 && y <= max_y)) return kNaN;
    const double u = std::clamp((x + 0.5) * scale_x - 0.5, 0.0, max_u);
    const double v = std::clamp((y + 0.5) * scale_y - 0.5, 0.0, max_v);
    const int u0 = static_cast<int>(u), v0 = static_cast<int>(v);  // u, v >= 0: truncation is floor
    const double fu = u - u0, fv = v - v0;                          // in [0, 1); 0 at the last column / row
    const float* row0 = map.data.data() + static_cast<size_t>(v0) * map.width;
    const float a = row0[u0];
    if (!Valid(a)) return kNaN;
    if (fv == 0.0) {
      if (fu == 0.0) return a;
      const float b = row0[u0 + 1];
      return Valid(b) ? (1.0 - fu) * a + fu * b : kNaN;
    }
    const float* row1 = row0 + map.width;
    const float c = row1[u0];
    if (!Valid(c)) return kNaN;
    if (fu == 0.0) return (1.0 - fv) * a + fv * c;
    const float b = row0[u0 + 1], d = row1[u0 + 1];
    if (!Valid(b) || !Valid(d)) return kNaN;
    return (1.0 - fv) * ((1.0 - fu) * a + fu * b) + fv * ((1.0 - fu) * c + fu * d);
  }

  const DepthMap& map;
  const bool ok;
  const double max_x, max_y, scale_x, scale_y, max_u, max_v;
};

}  // namespace

double SampleDepth(const DepthMap& map, double x, double y, int image_width, int image_height) {
  return Sampler(map, image_width, image_height)(x, y);
}

std::vector<double> SampleDepths(const DepthMap& map, const std::vector<Eigen::Vector2d>& points, int image_width,
                                 int image_height) {
  const Sampler sampler(map, image_width, image_height);
  std::vector<double> depths(points.size());
  for (size_t i = 0; i < points.size(); ++i) depths[i] = sampler(points[i].x(), points[i].y());
  return depths;
}

void CheckAspectRatio(const DepthMap& map, int image_width, int image_height, const std::string& name) {
  auto fail = [&](const std::string& problem) {
    throw std::runtime_error("depth file '" + name + "': " + problem);
  };
  if (map.Empty()) fail("empty depth map");
  if (image_width <= 0 || image_height <= 0) {
    fail("invalid image size " + std::to_string(image_width) + "x" + std::to_string(image_height));
  }
  const double map_aspect = static_cast<double>(map.width) / map.height;
  const double image_aspect = static_cast<double>(image_width) / image_height;
  if (std::abs(map_aspect / image_aspect - 1.0) > 0.01) {
    std::ostringstream msg;
    msg.precision(4);
    msg << "the depth map is " << map.width << "x" << map.height << " (aspect ratio " << map_aspect
        << ") but the image is " << image_width << "x" << image_height << " (aspect ratio " << image_aspect
        << "); they differ by more than 1%";
    fail(msg.str());
  }
}

}  // namespace madsfm
