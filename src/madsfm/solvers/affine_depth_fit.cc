#include "madsfm/solvers/affine_depth_fit.h"

#include <algorithm>
#include <cmath>

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

}  // namespace madsfm
