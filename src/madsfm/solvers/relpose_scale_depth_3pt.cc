#include "madsfm/solvers/relpose_scale_depth_3pt.h"

#include <cmath>

#include "madsfm/geometry/rigid_alignment.h"
#include "madsfm/solvers/affine_depth_solver_utils.h"

// Method. With shifts fixed to 0 the lifted points are P0_i = d0_i [x0_i; 1] and Q1_i = d1_i [x1_i; 1]
// (view 1 before the scale). Minimising sum_i ||scale Q1_i - (R P0_i + t)||^2 over (scale, R, t) is
// the Umeyama problem P0_i ~ s R' Q1_i + t' (multiply the residual by R^T, which keeps its norm):
// scale = s, R = R'^T, t = -R'^T t'. So AlignSimilarity runs with view 1 as the source.

namespace madsfm {

int SolveRelposeScaleDepth3pt(const std::vector<Eigen::Vector2d>& x0, const std::vector<Eigen::Vector2d>& x1,
                              const std::vector<double>& d0, const std::vector<double>& d1,
                              std::vector<AffineDepthPose>* models) {
  models->clear();
  if (!HasFiniteSample(x0, x1, d0, d1, 3)) return 0;
  Eigen::Vector3d P0[3], Q1[3];
  for (int i = 0; i < 3; ++i) {
    if (!(d0[i] > 0.0) || !(d1[i] > 0.0)) return 0;  // no shift can make a prior positive here
    P0[i] = Eigen::Vector3d(d0[i] * x0[i](0), d0[i] * x0[i](1), d0[i]);
    Q1[i] = Eigen::Vector3d(d1[i] * x1[i](0), d1[i] * x1[i](1), d1[i]);
  }
  double s;
  Eigen::Matrix3d R_10;
  Eigen::Vector3d t_10;
  if (!AlignSimilarity(Q1, P0, 3, &s, &R_10, &t_10)) return 0;
  AffineDepthPose m;
  m.R = R_10.transpose();
  m.t = -(m.R * t_10);
  m.scale = s;
  if (!IsValidAffineDepthModel(m, d0.data(), d1.data(), 3)) return 0;
  models->push_back(m);
  return 1;
}

}  // namespace madsfm
