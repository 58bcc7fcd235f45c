#include "madsfm/synthetic/multiview_scene.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <thread>
#include <utility>

#include "madsfm/synthetic/scene_primitives.h"

namespace madsfm {
namespace {

using synthetic::Box;
using synthetic::Rng;
using synthetic::SplitMix64;
using synthetic::ToLocal;
using synthetic::ToWorld;

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kMinT = 1e-9;

double DegToRad(double deg) { return deg * kPi / 180.0; }
double Clamp01(double v) { return std::min(1.0, std::max(0.0, v)); }

// ------------------------------------------------------------------------------------------------------------------
// Stateless hashing for the procedural textures: a cell (i, j) of a layer of a surface maps to a stream of
// uniform numbers.

inline uint64_t HashCell(uint64_t key, int64_t i, int64_t j) {
  return SplitMix64(key ^ SplitMix64(static_cast<uint64_t>(i) * 0x9E3779B97F4A7C15ULL +
                                     static_cast<uint64_t>(j) * 0xC2B2AE3D27D4EB4FULL));
}

class HashStream {
 public:
  explicit HashStream(uint64_t state) : state_(state) {}
  double Uniform() {
    state_ = SplitMix64(state_);
    return static_cast<double>(state_ >> 11) * 0x1.0p-53;
  }
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }

 private:
  uint64_t state_;
};

// 2-D gradient noise (Perlin-like) with 16 hashed gradient directions; output in about [-0.7, 0.7], mean 0.
inline double GradientNoise(uint64_t key, double x, double y) {
  static const double kGrad[16][2] = {{1.0, 0.0},  {0.9239, 0.3827},   {0.7071, 0.7071},   {0.3827, 0.9239},
                                      {0.0, 1.0},  {-0.3827, 0.9239},  {-0.7071, 0.7071},  {-0.9239, 0.3827},
                                      {-1.0, 0.0}, {-0.9239, -0.3827}, {-0.7071, -0.7071}, {-0.3827, -0.9239},
                                      {0.0, -1.0}, {0.3827, -0.9239},  {0.7071, -0.7071},  {0.9239, -0.3827}};
  const double fx = std::floor(x), fy = std::floor(y);
  const int64_t ix = static_cast<int64_t>(fx), iy = static_cast<int64_t>(fy);
  const double dx = x - fx, dy = y - fy;
  auto dot = [&](int64_t i, int64_t j, double ox, double oy) {
    const double* g = kGrad[HashCell(key, i, j) >> 60];
    return g[0] * ox + g[1] * oy;
  };
  const double n00 = dot(ix, iy, dx, dy), n10 = dot(ix + 1, iy, dx - 1.0, dy);
  const double n01 = dot(ix, iy + 1, dx, dy - 1.0), n11 = dot(ix + 1, iy + 1, dx - 1.0, dy - 1.0);
  const double sx = dx * dx * dx * (dx * (dx * 6.0 - 15.0) + 10.0);
  const double sy = dy * dy * dy * (dy * (dy * 6.0 - 15.0) + 10.0);
  const double a = n00 + sx * (n10 - n00), b = n01 + sx * (n11 - n01);
  return a + sy * (b - a);
}

// Share of the filter window [d - fw, d + fw] covered by the band [-hw, hw] (1-D box-filtered indicator).
inline double BandCoverage(double d, double hw, double fw) {
  const double overlap = std::min(d + fw, hw) - std::max(d - fw, -hw);
  return overlap <= 0.0 ? 0.0 : std::min(1.0, overlap / (2.0 * fw));
}

// Share of the filter window [d - fw, d + fw] with d' < 0 (box-filtered half-space; d = signed distance).
inline double InsideCoverage(double d, double fw) { return Clamp01((fw - d) / (2.0 * fw)); }

struct Rgb {
  double r = 0.0, g = 0.0, b = 0.0;
};
inline Rgb Lerp(const Rgb& a, const Rgb& b, double s) {
  return {a.r + s * (b.r - a.r), a.g + s * (b.g - a.g), a.b + s * (b.b - a.b)};
}
inline double Luma(const Rgb& c) { return 0.299 * c.r + 0.587 * c.g + 0.114 * c.b; }

Rgb Hsv(double h, double s, double v) {
  h = h - std::floor(h);
  const double c = v * s, hp = h * 6.0, x = c * (1.0 - std::abs(std::fmod(hp, 2.0) - 1.0)), m = v - c;
  Rgb out;
  if (hp < 1)
    out = {c, x, 0};
  else if (hp < 2)
    out = {x, c, 0};
  else if (hp < 3)
    out = {0, c, x};
  else if (hp < 4)
    out = {0, x, c};
  else if (hp < 5)
    out = {x, 0, c};
  else
    out = {c, 0, x};
  return {out.r + m, out.g + m, out.b + m};
}

// Random colour of a given brightness (value) range.
template <typename R>
Rgb RandomColor(R& rng, double v_lo, double v_hi) {
  return Hsv(rng.Uniform(), rng.Uniform(0.15, 0.85), rng.Uniform(v_lo, v_hi));
}

// Texture style of one planar surface (all lengths in metres).
struct SurfaceStyle {
  uint64_t key = 0;
  Rgb c0, c1, c2;                 // noise palette (c0/c1 differ in brightness), c2 = large-scale tint
  double noise_wavelength = 1.0;  // longest octave
  double blob_cell = 0.3, blob_prob = 0.6;
  double glyph_cell = 0.1, glyph_prob = 0.3;
  double stripe_prob = 0.1;
  double stripe_cell = 0.9;
};

SurfaceStyle MakeStyle(uint64_t key, double texture_scale) {
  HashStream h(key);
  SurfaceStyle s;
  s.key = key;
  const double v0 = h.Uniform(0.2, 0.85);
  const double v1 = v0 > 0.5 ? h.Uniform(0.05, v0 - 0.3) : h.Uniform(v0 + 0.3, 1.0);
  const double hue = h.Uniform();
  s.c0 = Hsv(hue, h.Uniform(0.1, 0.8), v0);
  s.c1 = Hsv(hue + h.Uniform(-0.25, 0.25), h.Uniform(0.1, 0.8), v1);
  s.c2 = RandomColor(h, 0.3, 0.9);
  s.noise_wavelength = texture_scale * h.Uniform(0.6, 1.4);
  s.blob_cell = texture_scale * h.Uniform(0.18, 0.4);
  s.blob_prob = h.Uniform(0.35, 0.75);
  s.glyph_cell = texture_scale * h.Uniform(0.07, 0.13);
  s.glyph_prob = h.Uniform(0.15, 0.4);
  s.stripe_prob = h.Uniform(0.0, 0.3);
  s.stripe_cell = texture_scale * 0.9;
  return s;
}

// Box-filtered fractal gradient noise; octaves finer than the filter width fade to their mean (0).
inline double FractalNoise(uint64_t key, double u, double v, double wavelength, int octaves, double falloff,
                           double filter) {
  double sum = 0.0, norm = 0.0, amp = 1.0, lambda = wavelength;
  for (int k = 0; k < octaves; ++k) {
    norm += amp;
    const double fade = Clamp01((lambda / filter - 2.0) * 0.5);
    if (fade <= 0.0) break;  // every finer octave is gone as well
    // Rotate and offset each octave so that the lattices do not line up.
    const double c = std::cos(1.1 * k + 0.3), s = std::sin(1.1 * k + 0.3);
    const double x = (c * u - s * v) / lambda + 17.31 * k, y = (s * u + c * v) / lambda - 9.17 * k;
    sum += fade * amp * GradientNoise(key + 0x1000 * k, x, y);
    amp *= falloff;
    lambda *= 0.5;
  }
  return norm > 0.0 ? sum / norm : 0.0;
}

// Letter-like glyphs: in a cell of the grid (size `cell`), with probability `prob`, 2-4 strokes between points of
// a 3 x 3 grid inside the cell. Returns the coverage in [0, 1] and the glyph colour.
inline double GlyphCoverage(uint64_t key, double u, double v, double cell, double prob, double fw, Rgb* color,
                            double base_luma) {
  const double cu = std::floor(u / cell), cv = std::floor(v / cell);
  HashStream h(HashCell(key, static_cast<int64_t>(cu), static_cast<int64_t>(cv)));
  if (h.Uniform() >= prob) return 0.0;
  const double hw = cell * h.Uniform(0.045, 0.085);
  if (hw < 0.15 * fw) return 0.0;
  const double span = cell * h.Uniform(0.26, 0.36);
  const double ox = (cu + 0.5) * cell, oy = (cv + 0.5) * cell;
  const double lx = u - ox, ly = v - oy;
  if (std::abs(lx) > span + hw + fw || std::abs(ly) > span + hw + fw) return 0.0;
  const double aspect = h.Uniform(0.7, 1.0);
  const int num_strokes = 2 + static_cast<int>(h.Uniform() * 3.0);
  double coverage = 0.0;
  for (int k = 0; k < num_strokes; ++k) {
    const int a = static_cast<int>(h.Uniform() * 9.0), b0 = static_cast<int>(h.Uniform() * 8.0);
    const int b = b0 >= a ? b0 + 1 : b0;  // distinct end points
    const double ax = ((a % 3) - 1) * span * aspect, ay = ((a / 3) - 1) * span;
    const double bx = ((b % 3) - 1) * span * aspect, by = ((b / 3) - 1) * span;
    const double dx = bx - ax, dy = by - ay;
    const double s = Clamp01(((lx - ax) * dx + (ly - ay) * dy) / (dx * dx + dy * dy));
    const double d = std::hypot(lx - ax - s * dx, ly - ay - s * dy);
    coverage = std::max(coverage, BandCoverage(d, hw, fw));
  }
  *color = base_luma > 0.5 ? RandomColor(h, 0.02, 0.25) : RandomColor(h, 0.75, 1.0);
  return coverage;
}

// Texture colour of a surface at face coordinates (u, v), box-filtered over a window of half-width fw.
Rgb EvaluateTexture(const SurfaceStyle& st, double u, double v, double fw) {
  const double filter = 2.0 * fw;
  // 1. Base: fractal noise between c0 and c1, tinted towards c2 by a second, smoother noise.
  const double n1 = FractalNoise(st.key, u, v, st.noise_wavelength, 9, 0.72, filter);
  const double n2 = FractalNoise(st.key ^ 0xABCDEF, u, v, 2.0 * st.noise_wavelength, 3, 0.5, filter);
  Rgb color = Lerp(st.c0, st.c1, Clamp01(0.5 + 2.2 * n1));
  color = Lerp(color, st.c2, 0.5 * Clamp01(0.5 + 2.5 * n2));
  const double base_luma = 0.5 * (Luma(st.c0) + Luma(st.c1));

  // 2. Rare small patches of stripes (a few periods each, random period and direction).
  {
    const double cell = st.stripe_cell;
    const double cu = std::floor(u / cell), cv = std::floor(v / cell);
    HashStream h(HashCell(st.key ^ 0x5151, static_cast<int64_t>(cu), static_cast<int64_t>(cv)));
    if (h.Uniform() < st.stripe_prob) {
      const double hx = cell * h.Uniform(0.1, 0.3), hy = cell * h.Uniform(0.1, 0.3);
      const double ox = (cu + 0.5) * cell + h.Uniform(-0.15, 0.15) * cell;
      const double oy = (cv + 0.5) * cell + h.Uniform(-0.15, 0.15) * cell;
      const double angle = h.Uniform(0.0, kPi), period = cell * h.Uniform(0.03, 0.09);
      const Rgb stripe_color = RandomColor(h, 0.0, 1.0);
      const double c = std::cos(angle), s = std::sin(angle);
      const double a = c * (u - ox) + s * (v - oy), b = -s * (u - ox) + c * (v - oy);
      const double inside = BandCoverage(a, hx, fw) * BandCoverage(b, hy, fw);
      if (inside > 0.0) {
        double value = 0.5;
        if (fw < 0.25 * period) {
          const double d = a - period * std::round(a / period);
          value = BandCoverage(d, 0.25 * period, fw) + BandCoverage(d - period, 0.25 * period, fw) +
                  BandCoverage(d + period, 0.25 * period, fw);
        }
        color = Lerp(color, stripe_color, inside * value);
      }
    }
  }

  // 3. Elliptic blobs (some with a concentric inner blob), up to one per cell, overlapping neighbouring cells.
  {
    const double cell = st.blob_cell;
    const int64_t cu = static_cast<int64_t>(std::floor(u / cell)), cv = static_cast<int64_t>(std::floor(v / cell));
    for (int64_t j = cv - 1; j <= cv + 1; ++j) {
      for (int64_t i = cu - 1; i <= cu + 1; ++i) {
        HashStream h(HashCell(st.key ^ 0xB10B, i, j));
        if (h.Uniform() >= st.blob_prob) continue;
        const double ox = (i + h.Uniform()) * cell, oy = (j + h.Uniform()) * cell;
        const double ra = cell * h.Uniform(0.12, 0.55), rb = cell * h.Uniform(0.12, 0.55);
        const double angle = h.Uniform(0.0, kPi);
        const double c = std::cos(angle), s = std::sin(angle);
        const double a = (c * (u - ox) + s * (v - oy)) / ra, b = (-s * (u - ox) + c * (v - oy)) / rb;
        const double rho = std::sqrt(a * a + b * b);
        const double r_min = std::min(ra, rb);
        if ((rho - 1.0) * r_min > fw) continue;
        const double size_fade = Clamp01(r_min / fw);
        const Rgb blob_color = RandomColor(h, 0.0, 1.0);
        color = Lerp(color, blob_color, size_fade * InsideCoverage((rho - 1.0) * r_min, fw));
        if (h.Uniform() < 0.4) {
          const double inner = h.Uniform(0.35, 0.6);
          const Rgb inner_color = RandomColor(h, 0.0, 1.0);
          const double fade = Clamp01(inner * r_min / fw);
          color = Lerp(color, inner_color, fade * InsideCoverage((rho - inner) * r_min, fw));
        }
      }
    }
  }

  // 4. Glyphs, small and large.
  Rgb glyph_color;
  double cov = GlyphCoverage(st.key ^ 0x6116, u, v, st.glyph_cell, st.glyph_prob, fw, &glyph_color, base_luma);
  if (cov > 0.0) color = Lerp(color, glyph_color, cov);
  cov = GlyphCoverage(st.key ^ 0x6117, u, v, 2.7 * st.glyph_cell, 0.5 * st.glyph_prob, fw, &glyph_color, base_luma);
  if (cov > 0.0) color = Lerp(color, glyph_color, cov);

  // 5. Fine multiplicative grain over everything, so that blobs and glyphs are not flat either.
  const double grain = 1.0 + 1.3 * FractalNoise(st.key ^ 0xDE7A11, u, v, 0.2 * st.noise_wavelength, 5, 0.8, filter);
  return {color.r * grain, color.g * grain, color.b * grain};
}

// ------------------------------------------------------------------------------------------------------------------
// Geometry: boxes yawed about the vertical z axis, an optional room (a box seen from inside) and an optional ground
// plane z = 0. Every face has its own surface id (and texture style).

// Slab test in a box's frame: entry/exit parameters and faces; false if the ray line misses the box.
bool IntersectSlabs(const Box& box, const Eigen::Vector3d& o, const Eigen::Vector3d& d, double* t_near, int* f_near,
                    double* t_far, int* f_far) {
  const Eigen::Vector3d lo = ToLocal(box, o - box.center), ld = ToLocal(box, d);
  double tn = -kInf, tf = kInf;
  int fn = -1, ff = -1;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(ld[k]) < 1e-15) {
      if (std::abs(lo[k]) > box.half[k]) return false;
      continue;
    }
    const double inv = 1.0 / ld[k];
    const double ta = (-box.half[k] - lo[k]) * inv, tb = (box.half[k] - lo[k]) * inv;
    const bool forward = ta <= tb;
    const double t1 = forward ? ta : tb, t2 = forward ? tb : ta;
    if (t1 > tn) tn = t1, fn = forward ? 2 * k : 2 * k + 1;
    if (t2 < tf) tf = t2, ff = forward ? 2 * k + 1 : 2 * k;
  }
  if (tn > tf) return false;
  *t_near = tn, *f_near = fn, *t_far = tf, *f_far = ff;
  return true;
}

struct Hit {
  double t = kInf;
  int box = -2;  // -1 = the room, -3 = the ground, >= 0 = boxes[box]
  int face = -1;
};

struct Scene {
  bool has_room = false;
  Box room;
  std::vector<Box> boxes;
  bool has_ground = false;
  int ground_surface = -1;
  int num_surfaces = 0;
  std::vector<SurfaceStyle> styles;
  Eigen::Vector3d light0 = Eigen::Vector3d(0.35, -0.55, 0.76).normalized();
  Eigen::Vector3d light1 = Eigen::Vector3d(-0.6, 0.5, 0.3).normalized();
};

bool Cast(const Scene& s, const Eigen::Vector3d& o, const Eigen::Vector3d& d, Hit* hit) {
  Hit best;
  double tn, tf;
  int fn, ff;
  if (s.has_room && IntersectSlabs(s.room, o, d, &tn, &fn, &tf, &ff) && tf > kMinT) {
    best.t = tf, best.box = -1, best.face = ff;
  }
  if (s.has_ground && d.z() < -1e-15 && o.z() > 0.0) {
    const double t = -o.z() / d.z();
    if (t > kMinT && t < best.t) best.t = t, best.box = -3, best.face = 0;
  }
  for (size_t i = 0; i < s.boxes.size(); ++i) {
    if (IntersectSlabs(s.boxes[i], o, d, &tn, &fn, &tf, &ff) && tn > kMinT && tn < best.t) {
      best.t = tn, best.box = static_cast<int>(i), best.face = fn;
    }
  }
  if (best.box == -2) return false;
  *hit = best;
  return true;
}

Box MakeBox(Scene* s, const Eigen::Vector3d& center, const Eigen::Vector3d& size, double yaw) {
  return synthetic::MakeBox(center, size, yaw, &s->num_surfaces);
}

// Surface id, visible normal (world) and face coordinates (u, v) of a hit point X.
void SurfaceAt(const Scene& s, const Hit& hit, const Eigen::Vector3d& X, int* surface, Eigen::Vector3d* normal,
               double* u, double* v) {
  if (hit.box == -3) {
    *surface = s.ground_surface;
    *normal = Eigen::Vector3d::UnitZ();
    *u = X.x(), *v = X.y();
    return;
  }
  const Box& b = hit.box == -1 ? s.room : s.boxes[hit.box];
  const Eigen::Vector3d l = ToLocal(b, X - b.center);
  const int k = hit.face / 2;
  Eigen::Vector3d n_local = Eigen::Vector3d::Zero();
  n_local[k] = (hit.face % 2 == 1) ? 1.0 : -1.0;  // outward
  if (hit.box == -1) n_local = -n_local;          // the room is seen from inside
  *normal = ToWorld(b, n_local);
  *u = l[(k + 1) % 3], *v = l[(k + 2) % 3];
  *surface = b.first_surface + hit.face;
}

// Is the horizontal footprint (centre, radius) free of the boxes placed so far?
bool FootprintFree(const Scene& s, const Eigen::Vector2d& c, double r, double margin) {
  for (const Box& b : s.boxes) {
    const double rb = b.half.head<2>().norm();
    if ((b.center.head<2>() - c).norm() < r + rb + margin) return false;
  }
  return true;
}

// ------------------------------------------------------------------------------------------------------------------
// Cameras.

MultiViewCamera LookAt(const Eigen::Vector3d& C, const Eigen::Vector3d& target, double roll, double focal, int width,
                       int height) {
  const Eigen::Vector3d f = (target - C).normalized();
  Eigen::Vector3d r = f.cross(Eigen::Vector3d::UnitZ());
  if (r.norm() < 1e-6) r = Eigen::Vector3d::UnitX();
  r.normalize();
  const Eigen::Vector3d d = f.cross(r);
  Eigen::Matrix3d R;
  R.row(0) = r.transpose();
  R.row(1) = d.transpose();
  R.row(2) = f.transpose();
  MultiViewCamera cam;
  cam.R = Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()).toRotationMatrix() * R;
  cam.t = -cam.R * C;
  cam.focal = focal;
  cam.cx = 0.5 * width;
  cam.cy = 0.5 * height;
  cam.width = width;
  cam.height = height;
  return cam;
}

// ------------------------------------------------------------------------------------------------------------------
// Scenes.

void BuildRoom(Rng& rng, int num_images, double focal, int width, int height, MultiViewMotion motion,
               double baseline_fraction, Scene* s, std::vector<MultiViewCamera>* cameras) {
  const double hx = rng.Uniform(3.8, 4.4), y_near = -4.2, y_far = rng.Uniform(2.8, 3.4), h = rng.Uniform(2.8, 3.2);
  s->has_room = true;
  s->room = MakeBox(s, Eigen::Vector3d(0.0, 0.5 * (y_near + y_far), 0.5 * h),
                    Eigen::Vector3d(2.0 * hx, y_far - y_near, h), 0.0);
  // Cabinets and shelves against the far wall.
  double x = -hx + rng.Uniform(0.05, 0.6);
  while (true) {
    const double w = rng.Uniform(0.7, 1.5);
    if (x + w > hx - 0.05) break;
    const double depth = rng.Uniform(0.4, 0.6), height = rng.Uniform(0.8, 2.2);
    s->boxes.push_back(MakeBox(s, Eigen::Vector3d(x + 0.5 * w, y_far - 0.5 * depth - 0.01, 0.5 * height),
                               Eigen::Vector3d(w, depth, height), 0.0));
    x += w + rng.Uniform(0.0, 0.9);
  }
  // Cabinets against the side walls, in the far half.
  for (int side = -1; side <= 1; side += 2) {
    const int count = rng.UniformInt(1, 2);
    double y = rng.Uniform(-1.0, -0.3);
    for (int i = 0; i < count; ++i) {
      const double w = rng.Uniform(0.7, 1.3), depth = rng.Uniform(0.4, 0.6), height = rng.Uniform(0.8, 2.0);
      if (y + w > y_far - 0.7) break;
      s->boxes.push_back(MakeBox(s, Eigen::Vector3d(side * (hx - 0.5 * depth - 0.01), y + 0.5 * w, 0.5 * height),
                                 Eigen::Vector3d(depth, w, height), 0.0));
      y += w + rng.Uniform(0.3, 1.2);
    }
  }
  // Crates (some stacked) and a pillar in the middle of the room.
  const int num_crates = rng.UniformInt(6, 9);
  for (int i = 0, attempts = 0; i < num_crates && attempts < 200; ++attempts) {
    const Eigen::Vector3d size(rng.Uniform(0.35, 1.0), rng.Uniform(0.35, 1.0), rng.Uniform(0.3, 1.1));
    const Eigen::Vector2d c(rng.Uniform(-hx + 1.0, hx - 1.0), rng.Uniform(-0.9, y_far - 1.0));
    const double r = 0.5 * size.head<2>().norm();
    if (!FootprintFree(*s, c, r, 0.1)) continue;
    const double yaw = rng.Uniform(0.0, kPi);
    s->boxes.push_back(MakeBox(s, Eigen::Vector3d(c.x(), c.y(), 0.5 * size.z()), size, yaw));
    if (rng.Uniform() < 0.4) {
      const Eigen::Vector3d top(size.x() * rng.Uniform(0.45, 0.75), size.y() * rng.Uniform(0.45, 0.75),
                                rng.Uniform(0.2, 0.5));
      s->boxes.push_back(
          MakeBox(s, Eigen::Vector3d(c.x(), c.y(), size.z() + 0.5 * top.z()), top, yaw + rng.Uniform(-0.4, 0.4)));
    }
    ++i;
  }
  for (int attempts = 0; attempts < 50; ++attempts) {
    const Eigen::Vector2d c(rng.Uniform(-hx + 1.0, hx - 1.0), rng.Uniform(0.0, y_far - 1.0));
    if (!FootprintFree(*s, c, 0.25, 0.2)) continue;
    s->boxes.push_back(
        MakeBox(s, Eigen::Vector3d(c.x(), c.y(), 0.5 * h), Eigen::Vector3d(0.3, 0.3, h), rng.Uniform(0.0, kPi)));
    break;
  }
  // Cameras on an arc of 60 degrees around the target, near the near wall, all looking at it.
  const Eigen::Vector3d target(rng.Uniform(-0.3, 0.3), rng.Uniform(0.3, 0.8), rng.Uniform(0.9, 1.2));
  const double radius = rng.Uniform(3.3, 3.7);
  if (motion == MultiViewMotion::kSideways) {
    // A straight walk along x at the arc's middle position, looking along +y at the target's height.
    const double length = baseline_fraction * radius, z = rng.Uniform(1.45, 1.65);
    for (int i = 0; i < num_images; ++i) {
      const double x = target.x() - 0.5 * length + length * i / (num_images - 1);
      const Eigen::Vector3d C(x, target.y() - radius, z + rng.Uniform(-0.02, 0.02) * length);
      const double yaw = DegToRad(rng.Uniform(-1.0, 1.0)), pitch = DegToRad(rng.Uniform(-1.0, 1.0));
      const Eigen::Vector3d dir(std::sin(yaw), std::cos(yaw), std::tan(pitch) + (target.z() - z) / radius);
      cameras->push_back(LookAt(C, C + dir, DegToRad(rng.Uniform(-1.0, 1.0)), focal, width, height));
    }
    return;
  }
  if (motion == MultiViewMotion::kForward) {
    // A level walk along +y towards the target from the arc's middle position, heading along it (pitched as kSideways).
    const double length = baseline_fraction * radius, z = rng.Uniform(1.45, 1.65);
    for (int i = 0; i < num_images; ++i) {
      const double y = target.y() - radius + length * i / (num_images - 1);
      const Eigen::Vector3d C(target.x() + rng.Uniform(-0.02, 0.02) * length, y,
                              z + rng.Uniform(-0.02, 0.02) * length);
      const double yaw = DegToRad(rng.Uniform(-1.0, 1.0)), pitch = DegToRad(rng.Uniform(-1.0, 1.0));
      const Eigen::Vector3d dir(std::sin(yaw), std::cos(yaw), std::tan(pitch) + (target.z() - z) / radius);
      cameras->push_back(LookAt(C, C + dir, DegToRad(rng.Uniform(-1.0, 1.0)), focal, width, height));
    }
    return;
  }
  if (motion == MultiViewMotion::kHandheld) {
    const Eigen::Vector3d centre(target.x(), target.y() - radius, rng.Uniform(1.45, 1.65));
    const double r = 0.5 * baseline_fraction * radius;
    for (int i = 0; i < num_images; ++i) {
      Eigen::Vector3d offset;
      do {
        offset = Eigen::Vector3d(rng.Uniform(-1.0, 1.0), rng.Uniform(-1.0, 1.0), rng.Uniform(-1.0, 1.0));
      } while (offset.norm() > 1.0);
      const Eigen::Vector3d C = centre + r * offset;
      const double jitter = radius * std::tan(DegToRad(3.0));
      const double dx = rng.Uniform(-jitter, jitter), dz = rng.Uniform(-jitter, jitter);
      const Eigen::Vector3d aim = target + Eigen::Vector3d(dx, 0.0, dz);
      cameras->push_back(LookAt(C, aim, DegToRad(rng.Uniform(-5.0, 5.0)), focal, width, height));
    }
    return;
  }
  for (int i = 0; i < num_images; ++i) {
    const double phi = DegToRad(-30.0 + 60.0 * i / (num_images - 1) + rng.Uniform(-1.0, 1.0));
    const Eigen::Vector3d C(target.x() + radius * std::sin(phi), target.y() - radius * std::cos(phi),
                            rng.Uniform(1.35, 1.75));
    const Eigen::Vector3d aim =
        target + Eigen::Vector3d(rng.Uniform(-0.15, 0.15), rng.Uniform(-0.15, 0.15), rng.Uniform(-0.15, 0.15));
    cameras->push_back(LookAt(C, aim, DegToRad(rng.Uniform(-3.0, 3.0)), focal, width, height));
  }
}

void BuildStreet(Rng& rng, int num_images, double focal, int width, int height, Scene* s,
                 std::vector<MultiViewCamera>* cameras) {
  s->has_ground = true;
  s->ground_surface = s->num_surfaces++;
  // Building blocks on both sides of the street (the street runs along x; facades at |y| = 7-8.5 m).
  for (int side = -1; side <= 1; side += 2) {
    double x = rng.Uniform(-30.0, -25.0);
    while (x < 70.0) {
      const double w = rng.Uniform(5.0, 12.0), depth = rng.Uniform(8.0, 12.0), height = rng.Uniform(6.0, 16.0);
      const double facade = rng.Uniform(7.0, 8.5);
      s->boxes.push_back(MakeBox(s, Eigen::Vector3d(x + 0.5 * w, side * (facade + 0.5 * depth), 0.5 * height),
                                 Eigen::Vector3d(w, depth, height), 0.0));
      x += w + (rng.Uniform() < 0.3 ? rng.Uniform(0.5, 2.0) : 0.0);
    }
  }
  // The building closing the street far ahead.
  const double end_x = rng.Uniform(55.0, 65.0), end_h = rng.Uniform(15.0, 25.0);
  s->boxes.push_back(
      MakeBox(s, Eigen::Vector3d(end_x + 5.0, 0.0, 0.5 * end_h), Eigen::Vector3d(10.0, 40.0, end_h), 0.0));
  // Parked cars (a body and a cabin) along both kerbs.
  const int num_cars = rng.UniformInt(4, 7);
  for (int i = 0, attempts = 0; i < num_cars && attempts < 200; ++attempts) {
    const int side = rng.Uniform() < 0.6 ? 1 : -1;
    const Eigen::Vector3d body(rng.Uniform(3.8, 4.6), rng.Uniform(1.7, 1.9), rng.Uniform(0.9, 1.1));
    const Eigen::Vector2d c(rng.Uniform(-6.0, 22.0), side * rng.Uniform(4.3, 5.0));
    if (!FootprintFree(*s, c, 0.5 * body.head<2>().norm(), 0.3)) continue;
    const double yaw = rng.Uniform(-0.05, 0.05);
    s->boxes.push_back(MakeBox(s, Eigen::Vector3d(c.x(), c.y(), 0.15 + 0.5 * body.z()), body, yaw));
    const Eigen::Vector3d cabin(body.x() * rng.Uniform(0.45, 0.6), body.y() * 0.85, rng.Uniform(0.4, 0.55));
    s->boxes.push_back(MakeBox(s, Eigen::Vector3d(c.x(), c.y(), 0.15 + body.z() + 0.5 * cabin.z()), cabin, yaw));
    ++i;
  }
  // Poles and bins on the pavements.
  const int num_poles = rng.UniformInt(3, 6);
  for (int i = 0; i < num_poles; ++i) {
    const int side = rng.Uniform() < 0.6 ? 1 : -1;
    const Eigen::Vector2d c(rng.Uniform(-5.0, 25.0), side * rng.Uniform(5.8, 6.6));
    if (!FootprintFree(*s, c, 0.3, 0.2)) continue;
    const bool bin = rng.Uniform() < 0.4;
    const Eigen::Vector3d size = bin ? Eigen::Vector3d(0.6, 0.6, 1.0) : Eigen::Vector3d(0.25, 0.25, 3.0);
    s->boxes.push_back(MakeBox(s, Eigen::Vector3d(c.x(), c.y(), 0.5 * size.z()), size, rng.Uniform(0.0, kPi)));
  }
  // Cameras walking 7 m along the street, looking across it at the left facades and a little forward.
  const double y0 = rng.Uniform(-2.8, -2.2);
  for (int i = 0; i < num_images; ++i) {
    const double x_cam = -1.0 + 7.0 * i / (num_images - 1) + rng.Uniform(-0.05, 0.05);
    const Eigen::Vector3d C(x_cam, y0 + rng.Uniform(-0.1, 0.1), 1.6 + rng.Uniform(-0.05, 0.05));
    const Eigen::Vector3d aim(6.0 + 0.5 * x_cam + rng.Uniform(-0.2, 0.2), 7.5, 3.5 + rng.Uniform(-0.2, 0.2));
    cameras->push_back(LookAt(C, aim, DegToRad(rng.Uniform(-3.0, 3.0)), focal, width, height));
  }
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// Runs body(row) for every row in [0, rows) on num_threads threads.
template <typename F>
void ParallelRows(int rows, int num_threads, const F& body) {
  if (num_threads <= 1) {
    for (int y = 0; y < rows; ++y) body(y);
    return;
  }
  std::atomic<int> next(0);
  std::vector<std::thread> threads;
  for (int k = 0; k < num_threads; ++k) {
    threads.emplace_back([&]() {
      for (int y = next++; y < rows; y = next++) body(y);
    });
  }
  for (std::thread& t : threads) t.join();
}

}  // namespace

// ------------------------------------------------------------------------------------------------------------------

void MultiViewSceneOptions::Check() const {
  auto fail = [](const std::string& what) { throw std::invalid_argument("MultiViewSceneOptions: " + what); };
  if (num_images < 2 || num_images > 1000) fail("num_images must be in [2, 1000]");
  if (image_width < 16 || image_height < 16 || image_width > 16384 || image_height > 16384)
    fail("image_width and image_height must be in [16, 16384]");
  if (!(fov_deg == 0.0 || (fov_deg >= 10.0 && fov_deg <= 150.0))) fail("fov_deg must be 0 or in [10, 150]");
  if (supersampling < 1 || supersampling > 8) fail("supersampling must be in [1, 8]");
  if (!(depth_map_scale > 0.0 && depth_map_scale <= 1.0)) fail("depth_map_scale must be in (0, 1]");
  if (!(prior_distortion >= 0.0 && prior_distortion <= 0.2)) fail("prior_distortion must be in [0, 0.2]");
  if (!(prior_min_scale > 0.0 && prior_max_scale >= prior_min_scale))
    fail("prior_min_scale must be > 0 and <= prior_max_scale");
  if (!(prior_max_shift_fraction >= 0.0 && prior_max_shift_fraction < 1.0))
    fail("prior_max_shift_fraction must be in [0, 1)");
  if (num_threads < 0) fail("num_threads must be >= 0");
  if (motion != MultiViewMotion::kArc && scene != MultiViewSceneType::kRoom)
    fail("motion sideways / handheld / forward needs the room scene");
  if (!(baseline_fraction > 0.0 && baseline_fraction <= 1.0)) fail("baseline_fraction must be in (0, 1]");
  if (!(per_image_fov_min_deg == 0.0 && per_image_fov_max_deg == 0.0) &&
      !(per_image_fov_min_deg >= 10.0 && per_image_fov_max_deg >= per_image_fov_min_deg &&
        per_image_fov_max_deg <= 150.0))
    fail("per_image_fov_min_deg / per_image_fov_max_deg must be 0 or 10 <= min <= max <= 150");
}

Eigen::Vector3d MultiViewCamera::RayDirection(double x, double y) const {
  return R.transpose() * Eigen::Vector3d((x - cx) / focal, (y - cy) / focal, 1.0);
}

bool MultiViewCamera::Project(const Eigen::Vector3d& X, Eigen::Vector2d* pixel, double* depth) const {
  const Eigen::Vector3d Xc = R * X + t;
  if (Xc.z() <= 1e-9) return false;
  *pixel = Eigen::Vector2d(focal * Xc.x() / Xc.z() + cx, focal * Xc.y() / Xc.z() + cy);
  *depth = Xc.z();
  return true;
}

const char* MultiViewSceneTypeName(MultiViewSceneType type) {
  return type == MultiViewSceneType::kRoom ? "room" : "street";
}

const char* MultiViewMotionName(MultiViewMotion motion) {
  switch (motion) {
    case MultiViewMotion::kArc:
      return "arc";
    case MultiViewMotion::kSideways:
      return "sideways";
    case MultiViewMotion::kHandheld:
      return "handheld";
    case MultiViewMotion::kForward:
      return "forward";
  }
  return "unknown";
}

struct MultiViewScene::Impl {
  MultiViewSceneOptions options;
  uint64_t seed = 0;
  double focal = 0.0;
  Scene scene;
  std::vector<MultiViewCamera> cameras;

  // Sky colour (street): a vertical gradient, no texture.
  static Rgb Sky(const Eigen::Vector3d& d) {
    const double e = Clamp01(d.z() / d.norm());
    return Lerp(Rgb{0.78, 0.85, 0.93}, Rgb{0.45, 0.62, 0.85}, e);
  }

  // Colour seen along the ray o + s d; fw_per_depth = half-width of the filter window per unit of z-depth along
  // the optical axis (metres / metre). *depth = the ray parameter of the hit (0 if none).
  Rgb Shade(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double fw_per_depth, double* depth) const {
    Hit hit;
    if (!Cast(scene, o, d, &hit)) {
      *depth = 0.0;
      return Sky(d);
    }
    *depth = hit.t;
    const Eigen::Vector3d X = o + hit.t * d;
    int surface;
    Eigen::Vector3d n;
    double u, v;
    SurfaceAt(scene, hit, X, &surface, &n, &u, &v);
    const double dn = d.norm();
    const double cos_incidence = std::max(0.1, std::abs(n.dot(d)) / dn);
    const double fw = fw_per_depth * hit.t * dn / cos_incidence;
    const Rgb albedo = EvaluateTexture(scene.styles[surface], u, v, fw);
    const double shade = 0.38 + 0.5 * std::max(0.0, n.dot(scene.light0)) + 0.17 * std::max(0.0, n.dot(scene.light1));
    return {albedo.r * shade, albedo.g * shade, albedo.b * shade};
  }
};

MultiViewScene::MultiViewScene(const MultiViewSceneOptions& options, uint64_t seed) : impl_(new Impl) {
  options.Check();
  impl_->options = options;
  impl_->seed = seed;
  Rng rng(SplitMix64(seed ^ 0x6D756C7469766965ULL));
  const double fov = options.fov_deg > 0.0 ? options.fov_deg : rng.Uniform(60.0, 70.0);
  impl_->focal = 0.5 * options.image_width / std::tan(0.5 * DegToRad(fov));
  if (options.scene == MultiViewSceneType::kRoom) {
    BuildRoom(rng, options.num_images, impl_->focal, options.image_width, options.image_height, options.motion,
              options.baseline_fraction, &impl_->scene, &impl_->cameras);
  } else {
    BuildStreet(rng, options.num_images, impl_->focal, options.image_width, options.image_height, &impl_->scene,
                &impl_->cameras);
  }
  if (options.per_image_fov_max_deg > 0.0) {
    Rng focal_rng(SplitMix64(seed ^ 0x666F63616C73ULL));
    for (MultiViewCamera& cam : impl_->cameras) {
      const double f = focal_rng.Uniform(options.per_image_fov_min_deg, options.per_image_fov_max_deg);
      cam.focal = 0.5 * options.image_width / std::tan(0.5 * DegToRad(f));
    }
  }
  const double texture_scale = options.scene == MultiViewSceneType::kRoom ? 1.0 : 2.5;
  impl_->scene.styles.reserve(impl_->scene.num_surfaces);
  for (int i = 0; i < impl_->scene.num_surfaces; ++i) {
    impl_->scene.styles.push_back(MakeStyle(SplitMix64(seed * 0x100000001B3ULL + 7919 * (i + 1)), texture_scale));
  }
}

MultiViewScene::~MultiViewScene() = default;
MultiViewScene::MultiViewScene(MultiViewScene&&) noexcept = default;
MultiViewScene& MultiViewScene::operator=(MultiViewScene&&) noexcept = default;

const MultiViewSceneOptions& MultiViewScene::options() const { return impl_->options; }
int MultiViewScene::NumImages() const { return static_cast<int>(impl_->cameras.size()); }
const MultiViewCamera& MultiViewScene::Camera(int image) const { return impl_->cameras.at(image); }
double MultiViewScene::Focal() const { return impl_->focal; }

std::string MultiViewScene::ImageName(int image) {
  char name[32];
  std::snprintf(name, sizeof(name), "img_%03d.png", image);
  return name;
}

bool MultiViewScene::CastRay(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double* s) const {
  Hit hit;
  if (!Cast(impl_->scene, origin, direction, &hit)) return false;
  *s = hit.t;
  return true;
}

double MultiViewScene::DepthAt(int image, double x, double y) const {
  const MultiViewCamera& cam = Camera(image);
  double s;
  return CastRay(cam.Center(), cam.RayDirection(x, y), &s) ? s : 0.0;
}

MultiViewImage MultiViewScene::Render(int image) const {
  const MultiViewSceneOptions& o = impl_->options;
  const MultiViewCamera& cam = Camera(image);
  const int W = cam.width, H = cam.height, S = o.supersampling;
  const int num_threads =
      o.num_threads > 0 ? o.num_threads : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  MultiViewImage out;
  out.name = ImageName(image);
  out.camera = cam;
  out.rgb.assign(static_cast<size_t>(W) * H * 3, 0);
  out.depth.width = W;
  out.depth.height = H;
  out.depth.data.assign(static_cast<size_t>(W) * H, 0.0f);

  // Colour: S x S rays per pixel, each texture lookup box-filtered over its share of the pixel footprint.
  const Eigen::Vector3d C = cam.Center();
  const double fw_per_depth = 0.5 / (cam.focal * S);
  ParallelRows(H, num_threads, [&](int y) {
    for (int x = 0; x < W; ++x) {
      Rgb sum;
      double depth;
      for (int sy = 0; sy < S; ++sy) {
        for (int sx = 0; sx < S; ++sx) {
          const Rgb c = impl_->Shade(C, cam.RayDirection(x + (sx + 0.5) / S, y + (sy + 0.5) / S), fw_per_depth, &depth);
          sum.r += c.r, sum.g += c.g, sum.b += c.b;
        }
      }
      const double inv = 1.0 / (S * S);
      uint8_t* px = &out.rgb[(static_cast<size_t>(y) * W + x) * 3];
      px[0] = static_cast<uint8_t>(std::lround(255.0 * Clamp01(sum.r * inv)));
      px[1] = static_cast<uint8_t>(std::lround(255.0 * Clamp01(sum.g * inv)));
      px[2] = static_cast<uint8_t>(std::lround(255.0 * Clamp01(sum.b * inv)));
      out.depth.data[static_cast<size_t>(y) * W + x] = static_cast<float>(DepthAt(image, x + 0.5, y + 0.5));
    }
  });

  // Exact depth at the prior resolution.
  const int w = std::max(1, static_cast<int>(std::lround(W * o.depth_map_scale)));
  const int h = std::max(1, static_cast<int>(std::lround(H * o.depth_map_scale)));
  std::vector<double> z(static_cast<size_t>(w) * h);
  ParallelRows(h, num_threads, [&](int v) {
    for (int u = 0; u < w; ++u)
      z[static_cast<size_t>(v) * w + u] = DepthAt(image, (u + 0.5) * W / w, (v + 0.5) * H / h);
  });
  std::vector<double> valid;
  double max_depth = 0.0;
  for (const double d : z) {
    if (d > 0.0) valid.push_back(d), max_depth = std::max(max_depth, d);
  }
  out.median_depth = Median(valid);
  const double sky_depth = max_depth > 0.0 ? 2.0 * max_depth : 1.0;
  const double median = out.median_depth > 0.0 ? out.median_depth : 1.0;

  // Smooth non-affine distortion (see the header): z' = z (1 + delta(x, y)) (1 + 2 gamma (r - 1) / (r + 1)).
  Rng rng(SplitMix64(impl_->seed ^ SplitMix64(0x7072696F72ULL + static_cast<uint64_t>(image))));
  const double dist = o.prior_distortion;
  double coeff[5];
  for (double& c : coeff) c = 0.5 * dist * rng.Uniform(-1.0, 1.0);
  const double sin_amp = dist * rng.Uniform(0.3, 0.6), sin_angle = rng.Uniform(0.0, 2.0 * kPi);
  const double sin_freq = rng.Uniform(1.5, 3.0), sin_phase = rng.Uniform(0.0, 2.0 * kPi);
  const double gamma = dist * rng.Uniform(-1.0, 1.0);
  std::vector<double> zd(z.size());
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const size_t i = static_cast<size_t>(v) * w + u;
      const double xn = ((u + 0.5) * W / w - cam.cx) / (0.5 * W), yn = ((v + 0.5) * H / h - cam.cy) / (0.5 * W);
      const double delta =
          coeff[0] * xn + coeff[1] * yn + coeff[2] * xn * yn + coeff[3] * xn * xn + coeff[4] * yn * yn +
          sin_amp * std::sin(sin_freq * (std::cos(sin_angle) * xn + std::sin(sin_angle) * yn) + sin_phase);
      const double zz = z[i] > 0.0 ? z[i] : sky_depth;
      const double r = zz / median;
      zd[i] = zz * (1.0 + delta) * (1.0 + 2.0 * gamma * (r - 1.0) / (r + 1.0));
    }
  }
  // Unknown affine transform: z' = a d + b, every d > 0.
  const double a = rng.LogUniform(o.prior_min_scale, o.prior_max_scale);
  const double min_zd = *std::min_element(zd.begin(), zd.end());
  const double zd_median = Median(zd);
  const double b_lo = -o.prior_max_shift_fraction * zd_median;
  const double b_hi = std::min(o.prior_max_shift_fraction * zd_median, 0.8 * min_zd);
  const double b = rng.Uniform(b_lo, std::max(b_lo, b_hi));
  out.prior_scale = a;
  out.prior_shift = b;
  out.prior.width = out.prior_true_depth.width = out.prior_undistorted.width = w;
  out.prior.height = out.prior_true_depth.height = out.prior_undistorted.height = h;
  out.prior.data.resize(z.size());
  out.prior_true_depth.data.resize(z.size());
  out.prior_undistorted.data.resize(z.size());
  for (size_t i = 0; i < z.size(); ++i) {
    out.prior.data[i] = static_cast<float>((zd[i] - b) / a);
    out.prior_true_depth.data[i] = static_cast<float>(z[i]);
    out.prior_undistorted.data[i] = static_cast<float>(((z[i] > 0.0 ? z[i] : sky_depth) - b) / a);
  }
  return out;
}

}  // namespace madsfm
