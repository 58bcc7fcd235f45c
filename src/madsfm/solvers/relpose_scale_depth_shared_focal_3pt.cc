#include "madsfm/solvers/relpose_scale_depth_shared_focal_3pt.h"

#include <cmath>

#include "madsfm/geometry/rigid_alignment.h"
#include "madsfm/solvers/univariate.h"

// Derivation (w = 1/f^2, g = scale^2, in normalised units, see below). The lifted points
// P0_i = d0_i [p0_i / f; 1] and P1_i = scale d1_i [p1_i / f; 1] have equal pairwise distances:
//   w c0_jk + e0_jk = g (w c1_jk + e1_jk),   c0_jk = ||d0_j p0_j - d0_k p0_k||^2, e0_jk = (d0_j - d0_k)^2.
// The pairs a = (0, 1) and b = (1, 2) are used (they involve all three points; the pair (0, 2) is not
// enforced and is not used to reject roots). Each gives w (c0 - g c1) = g e1 - e0; eliminating w:
//   (g e1_a - e0_a)(c0_b - g c1_b) = (g e1_b - e0_b)(c0_a - g c1_a),
// a quadratic in g (<= 2 solutions). w is the least-squares solution of the two linear equations in w
// (exact for an exact root, and well defined unless both coefficients vanish). R, t by rigid alignment
// of the 3 lifted point pairs.
//
// Normalisation: pixel coordinates are divided by their RMS radius s over both views, depth priors by
// the mean absolute prior m0, m1 of each view; f = s / sqrt(w'), scale = sqrt(g') m0 / m1.

namespace madsfm {

int SolveRelposeScaleDepthSharedFocal3pt(const std::vector<Eigen::Vector2d>& p0, const std::vector<Eigen::Vector2d>& p1,
                                         const std::vector<double>& d0, const std::vector<double>& d1,
                                         std::vector<AffineDepthPose>* models) {
  models->clear();
  if (p0.size() < 3 || p1.size() < 3 || d0.size() < 3 || d1.size() < 3) return 0;

  double sq_radius = 0.0, m0 = 0.0, m1 = 0.0;
  for (int i = 0; i < 3; ++i) {
    sq_radius += p0[i].squaredNorm() + p1[i].squaredNorm();
    m0 += std::abs(d0[i]);
    m1 += std::abs(d1[i]);
  }
  const double s = std::sqrt(sq_radius / 6.0);
  m0 /= 3.0;
  m1 /= 3.0;
  if (!(s > 0.0) || !(m0 > 0.0) || !(m1 > 0.0) || !std::isfinite(s) || !std::isfinite(m0) || !std::isfinite(m1)) {
    return 0;
  }
  for (int i = 0; i < 3; ++i) {
    if (!(d0[i] > 0.0) || !(d1[i] > 0.0)) return 0;  // no shifts: every prior must be a valid depth
  }

  constexpr int kPairs[2][2] = {{0, 1}, {1, 2}};
  double c0[2], e0[2], c1[2], e1[2];
  for (int r = 0; r < 2; ++r) {
    const int j = kPairs[r][0], k = kPairs[r][1];
    const double z0j = d0[j] / m0, z0k = d0[k] / m0, z1j = d1[j] / m1, z1k = d1[k] / m1;
    c0[r] = (z0j * p0[j] / s - z0k * p0[k] / s).squaredNorm();
    c1[r] = (z1j * p1[j] / s - z1k * p1[k] / s).squaredNorm();
    e0[r] = (z0j - z0k) * (z0j - z0k);
    e1[r] = (z1j - z1k) * (z1j - z1k);
  }
  // q2 g^2 + q1 g + q0 = 0.
  const double q2 = e1[1] * c1[0] - e1[0] * c1[1];
  const double q1 = e1[0] * c0[1] + e0[0] * c1[1] - e1[1] * c0[0] - e0[1] * c1[0];
  const double q0 = e0[1] * c0[0] - e0[0] * c0[1];
  // Degenerate when the quadratic vanishes identically (relative to the size of its terms).
  const double mag = std::abs(e1[1] * c1[0]) + std::abs(e1[0] * c1[1]) + std::abs(e1[0] * c0[1]) +
                     std::abs(e0[0] * c1[1]) + std::abs(e1[1] * c0[0]) + std::abs(e0[1] * c1[0]) +
                     std::abs(e0[1] * c0[0]) + std::abs(e0[0] * c0[1]);
  if (!(mag > 0.0) || !std::isfinite(mag) || std::abs(q2) + std::abs(q1) + std::abs(q0) <= 1e-14 * mag) {
    return 0;
  }
  double g_roots[2];
  const int num_g = SolveQuadraticReal(q2, q1, q0, g_roots);
  models->reserve(num_g);
  for (int k = 0; k < num_g; ++k) {
    const double g = g_roots[k];
    if (!(g > 0.0) || !std::isfinite(g)) continue;
    double num = 0.0, den = 0.0;
    for (int r = 0; r < 2; ++r) {
      const double a = c0[r] - g * c1[r], b = g * e1[r] - e0[r];  // a w = b
      num += a * b;
      den += a * a;
    }
    const double w = num / den;
    if (!(w > 0.0) || !std::isfinite(w)) continue;

    AffineDepthPose model;
    const double f = s / std::sqrt(w);
    model.f0 = model.f1 = f;
    model.scale = std::sqrt(g) * m0 / m1;
    Eigen::Vector3d P0[3], P1[3];
    for (int i = 0; i < 3; ++i) {
      P0[i] = model.Depth0(d0[i]) * Eigen::Vector3d(p0[i].x() / f, p0[i].y() / f, 1.0);
      P1[i] = model.Depth1(d1[i]) * Eigen::Vector3d(p1[i].x() / f, p1[i].y() / f, 1.0);
    }
    if (!AlignRigid(P0, P1, 3, &model.R, &model.t)) continue;
    if (!std::isfinite(f) || !(f > 0.0) || !std::isfinite(model.scale) || !(model.scale > 0.0) ||
        !model.t.allFinite()) {
      continue;
    }
    models->push_back(model);
  }
  return static_cast<int>(models->size());
}

}  // namespace madsfm
