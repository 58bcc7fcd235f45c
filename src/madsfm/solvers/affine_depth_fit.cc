#include "madsfm/solvers/affine_depth_fit.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "madsfm/geometry/triangulation.h"

namespace madsfm {
namespace {

// Least-squares fit of d = a * z - b (unknowns a, b) or d = a * z (b = 0), accumulated in one
// pass; the centred moments use Welford's updates to avoid cancellation.
struct LineFit {
  double n = 0.0, mean_z = 0.0, mean_d = 0.0, m_zz = 0.0, m_zd = 0.0;  // centred sums
  double s_zz = 0.0, s_zd = 0.0;                                        // raw sums (no shift)
  void Add(double z, double d) {
    n += 1.0;
    const double dz = z - mean_z;
    mean_z += dz / n;
    mean_d += (d - mean_d) / n;
    m_zz += dz * (z - mean_z);
    m_zd += dz * (d - mean_d);
    s_zz += z * z;
    s_zd += z * d;
  }
  // Returns false when the fit is not determined (fewer than 2 points or all z equal).
  bool Solve(bool fit_shift, double* a, double* b) const {
    if (n < 2.0) return false;
    if (!fit_shift) {
      if (!(s_zz > 0.0)) return false;
      *a = s_zd / s_zz;
      *b = 0.0;
      return std::isfinite(*a);
    }
    // a = cov(z, d) / var(z), b = a * mean(z) - mean(d).
    if (!(m_zz > 1e-12 * n * mean_z * mean_z)) return false;
    *a = m_zd / m_zz;
    *b = *a * mean_z - mean_d;
    return std::isfinite(*a) && std::isfinite(*b);
  }
};

}  // namespace

bool FitAffineDepthToPose(const std::vector<Eigen::Vector2d>& x0, const std::vector<Eigen::Vector2d>& x1,
                          const std::vector<double>& d0, const std::vector<double>& d1, AffineDepthPose* model,
                          bool fit_shift) {
  const double t_norm = model->t.norm();
  if (!(t_norm > 0.0) || !std::isfinite(t_norm) || !model->R.allFinite()) return false;
  const Eigen::Vector3d t_unit = model->t / t_norm;
  const size_t n = std::min(std::min(x0.size(), x1.size()), std::min(d0.size(), d1.size()));

  // With the unit translation, the triangulated depths z0, z1 are k times too small (k = |t| in
  // prior units): d0 = k z0 - shift0 and d1 = (k / scale) z1 - shift1.
  LineFit fit0, fit1;
  for (size_t i = 0; i < n; ++i) {
    const bool has0 = std::isfinite(d0[i]), has1 = std::isfinite(d1[i]);
    if (!has0 && !has1) continue;
    double z0, z1;
    if (!TriangulateDepths(model->R, t_unit, x0[i], x1[i], &z0, &z1) || !(z0 > 0.0) || !(z1 > 0.0)) continue;
    if (has0) fit0.Add(z0, d0[i]);
    if (has1) fit1.Add(z1, d1[i]);
  }
  double k, shift0, k_over_scale, shift1;
  if (!fit0.Solve(fit_shift, &k, &shift0) || !fit1.Solve(fit_shift, &k_over_scale, &shift1)) return false;
  if (!(k > 0.0) || !(k_over_scale > 0.0)) return false;
  const double scale = k / k_over_scale;
  if (!(scale > 0.0) || !std::isfinite(scale)) return false;
  model->t = k * t_unit;
  model->scale = scale;
  model->shift0 = shift0;
  model->shift1 = shift1;
  return true;
}

namespace {

// Iteratively reweighted least squares of the Huber fit: rounds until the fitted line moves by less than this
// share of its size, at most kMaxHuberRounds. Four fixed rounds (madsfm-21 and before) stopped far from the Huber
// fit: on planar pairs the slope still changed by 25% between rounds 4 and 10.
constexpr double kHuberTolerance = 1e-6;
constexpr int kMaxHuberRounds = 50;

// Weighted robust fit z ~ alpha d + beta (beta = 0 without shift) over (d, z, w); false when undetermined.
bool WeightedLineFit(const std::vector<double>& d, const std::vector<double>& z, const std::vector<double>& w,
                     bool fit_shift, double max_shift, double* alpha, double* beta) {
  const size_t n = d.size();
  if (n < 2) return false;
  std::vector<double> robust(n, 1.0), rel(n);
  double a = 0.0, b = 0.0, max_d = 0.0;
  for (double v : d) max_d = std::max(max_d, std::abs(v));
  for (int round = 0; round < kMaxHuberRounds; ++round) {
    double sw = 0, sd = 0, sz = 0;
    for (size_t i = 0; i < n; ++i) {
      const double wi = w[i] * robust[i];
      sw += wi, sd += wi * d[i], sz += wi * z[i];
    }
    if (!(sw > 0.0)) return false;
    double a_new, b_new;
    if (fit_shift) {
      const double md = sd / sw, mz = sz / sw;
      double sdd = 0, sdz = 0;
      for (size_t i = 0; i < n; ++i) {
        const double wi = w[i] * robust[i];
        sdd += wi * (d[i] - md) * (d[i] - md);
        sdz += wi * (d[i] - md) * (z[i] - mz);
      }
      if (!(sdd > 1e-12 * sw * md * md)) return false;
      a_new = sdz / sdd;
      b_new = mz - a_new * md;
      if (max_shift > 0.0 && !(a_new > 0.0 && std::abs(b_new) <= max_shift * a_new)) {
        // Outside the cone of admissible lines: the best line on one of its two edges, z = a (d +- max_shift).
        double best = std::numeric_limits<double>::infinity();
        for (double sign : {-1.0, 1.0}) {
          const double shift = sign * max_shift;
          double s_uu = 0, s_uz = 0, s_zz = 0;
          for (size_t i = 0; i < n; ++i) {
            const double wi = w[i] * robust[i], u = d[i] + shift;
            s_uu += wi * u * u, s_uz += wi * u * z[i], s_zz += wi * z[i] * z[i];
          }
          if (!(s_uu > 0.0)) continue;
          const double a_edge = s_uz / s_uu, cost = s_zz - s_uz * a_edge;
          if (a_edge > 0.0 && cost < best) best = cost, a_new = a_edge, b_new = shift * a_edge;
        }
        if (!(best < std::numeric_limits<double>::infinity())) return false;
      }
    } else {
      double sdd = 0, sdz = 0;
      for (size_t i = 0; i < n; ++i) {
        const double wi = w[i] * robust[i];
        sdd += wi * d[i] * d[i];
        sdz += wi * d[i] * z[i];
      }
      if (!(sdd > 0.0)) return false;
      a_new = sdz / sdd;
      b_new = 0.0;
    }
    if (!std::isfinite(a_new) || !std::isfinite(b_new)) return false;
    // How far the line moved over the range of the priors, against its size there.
    const double moved = std::abs(a_new - a) * max_d + std::abs(b_new - b);
    const double size = std::abs(a_new) * max_d + std::abs(b_new);
    a = a_new, b = b_new;
    if (round > 0 && moved <= kHuberTolerance * size) break;
    // Huber weights on the relative residuals, scaled by their weighted median absolute value.
    for (size_t i = 0; i < n; ++i) rel[i] = std::abs(a * d[i] + b - z[i]) * std::sqrt(w[i]);  // whitened
    std::vector<double> sorted = rel;
    std::nth_element(sorted.begin(), sorted.begin() + n / 2, sorted.end());
    const double scale = 1.4826 * sorted[n / 2];
    if (!(scale > 0.0)) break;
    const double c = 1.345 * scale;
    for (size_t i = 0; i < n; ++i) robust[i] = rel[i] <= c ? 1.0 : c / rel[i];
  }
  *alpha = a;
  *beta = b;
  return true;
}

}  // namespace

bool FitAffineDepthToPoseWeighted(const std::vector<Eigen::Vector2d>& x0, const std::vector<Eigen::Vector2d>& x1,
                                  const std::vector<double>& d0, const std::vector<double>& d1, double angular_noise,
                                  AffineDepthPose* model, bool fit_shift, double prior_sigma, double max_shift0,
                                  double max_shift1) {
  const double t_norm = model->t.norm();
  if (!(t_norm > 0.0) || !std::isfinite(t_norm) || !model->R.allFinite()) return false;
  const Eigen::Vector3d t_unit = model->t / t_norm;
  const size_t n = std::min(std::min(x0.size(), x1.size()), std::min(d0.size(), d1.size()));
  std::vector<double> pd0, pz0, pw0, pd1, pz1, pw1;
  for (size_t i = 0; i < n; ++i) {
    const bool has0 = std::isfinite(d0[i]), has1 = std::isfinite(d1[i]);
    if (!has0 && !has1) continue;
    double z0, z1;
    if (!TriangulateDepths(model->R, t_unit, x0[i], x1[i], &z0, &z1) || !(z0 > 0.0) || !(z1 > 0.0)) continue;
    const Eigen::Vector3d r0 = model->R * Eigen::Vector3d(x0[i].x(), x0[i].y(), 1.0);
    const Eigen::Vector3d r1(x1[i].x(), x1[i].y(), 1.0);
    const double sin2 = r0.cross(r1).squaredNorm() / (r0.squaredNorm() * r1.squaredNorm());
    // Weight of the relative residual, then of the absolute one (divided by z^2).
    const double w = 1.0 / (prior_sigma * prior_sigma + angular_noise * angular_noise / std::max(sin2, 1e-300));
    if (has0) pd0.push_back(d0[i]), pz0.push_back(z0), pw0.push_back(w / (z0 * z0));
    if (has1) pd1.push_back(d1[i]), pz1.push_back(z1), pw1.push_back(w / (z1 * z1));
  }
  // z0 = (d0 + shift0) / k: alpha0 = 1 / k, beta0 = shift0 / k; z1 = scale (d1 + shift1) / k likewise.
  double a0, b0, a1, b1;
  if (!WeightedLineFit(pd0, pz0, pw0, fit_shift, max_shift0, &a0, &b0) ||
      !WeightedLineFit(pd1, pz1, pw1, fit_shift, max_shift1, &a1, &b1)) {
    return false;
  }
  if (!(a0 > 0.0) || !(a1 > 0.0)) return false;
  const double k = 1.0 / a0;
  const double scale = k * a1;
  if (!std::isfinite(k) || !(scale > 0.0) || !std::isfinite(scale)) return false;
  model->t = k * t_unit;
  model->scale = scale;
  model->shift0 = fit_shift ? b0 / a0 : 0.0;
  model->shift1 = fit_shift ? b1 / a1 : 0.0;
  return true;
}

}  // namespace madsfm
