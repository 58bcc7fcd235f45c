// Small shared pieces of the affine-depth minimal solvers (calibrated, shared focal, two focal):
// input checks, normalisation, the coefficients of the pairwise distance equations, pose recovery
// from lifted points and the mapping between a problem and its view-swapped twin.
// Private to src/madsfm/solvers; not part of the public API.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <cmath>
#include <vector>

#include "madsfm/geometry/affine_depth_pose.h"

namespace madsfm {

// True if the four inputs hold at least n entries each and the first n are all finite.
bool HasFiniteSample(const std::vector<Eigen::Vector2d>& x0, const std::vector<Eigen::Vector2d>& x1,
                     const std::vector<double>& d0, const std::vector<double>& d1, int n);

// Mean of |v[i]|, i < n: the depth normaliser of one view (0 if all are zero).
double MeanAbs(const double* v, int n);

// Root-mean-square norm of p[i], i < n: the pixel normaliser of one view (0 if all are zero).
double RmsNorm(const Eigen::Vector2d* p, int n);

// Coefficients of the squared distance between two lifted points of one view as a function of
// the view's shift b, split into image-plane and depth parts:
//   ||(d_j + b) x_j - (d_k + b) x_k||^2 = A b^2 + B b + C,   (d_j - d_k)^2 = E,
// returned as (A, B, C, E). For normalised coordinates the 3-D squared distance
// ||(d_j + b) [x_j;1] - (d_k + b) [x_k;1]||^2 is A b^2 + B b + (C + E); for pixel coordinates and
// focal f (w = 1/f^2) it is w (A b^2 + B b + C) + E.
Eigen::Vector4d PairDistanceCoefficients(const Eigen::Vector2d& x_j, const Eigen::Vector2d& x_k, double d_j,
                                         double d_k);

// |det(M)| / prod_i ||row_i(M)||, in [0, 1]: a cheap, row-scale-invariant conditioning measure
// (1 for orthogonal rows, 0 for singular or non-finite M).
template <int N>
double HadamardRatio(const Eigen::Matrix<double, N, N>& M) {
  double denom = 1.0;
  for (int i = 0; i < N; ++i) denom *= M.row(i).norm();
  const double r = std::abs(M.determinant()) / denom;
  return r >= 0.0 && r <= 1.0 + 1e-9 ? r : 0.0;  // also rejects NaN
}

// Exact rigid transform (R proper, q_i = R p_i + t) between two congruent triangles p, q (3 points
// each, equal side lengths), from orthonormal frames built on each triangle (cheaper than an SVD;
// for nearly congruent triangles it is a good but not least-squares estimate). Returns false for
// (nearly) collinear or non-finite input.
bool AlignCongruentTriangles(const Eigen::Vector3d* p, const Eigen::Vector3d* q, Eigen::Matrix3d* R,
                             Eigen::Vector3d* t);

// A model of the problem with the two views exchanged (x0 <-> x1, d0 <-> d1), from a model of the
// original problem: scale' = 1/scale, shift0' = shift1, shift1' = shift0, f0' = f1, f1' = f0,
// R' = R^T, t' = -R^T t / scale. (From scale (d1 + shift1) [x1;1] = R (d0 + shift0) [x0;1] + t:
// (1/scale) (d0 + shift0) [x0;1] = R^T (d1 + shift1) [x1;1] - R^T t / scale, and the new t is in
// units of the new view 0's corrected depth d1 + shift1.) The mapping is its own inverse.
AffineDepthPose SwapViews(const AffineDepthPose& model);

// True if every entry of the model is finite, scale, f0 and f1 are > 0 and the corrected depths
// Depth0(d0[i]) and Depth1(d1[i]) of the first n priors are > 0.
bool IsValidAffineDepthModel(const AffineDepthPose& model, const double* d0, const double* d1, int n);

}  // namespace madsfm
