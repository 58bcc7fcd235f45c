// Gives a point-based relative pose the depth parameters of the affine-depth model (paper Sec. 4.4):
// triangulate the correspondences with the pose, then fit scale and shifts by least squares.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "madsfm/geometry/affine_depth_pose.h"

namespace madsfm {

// x0[i], x1[i]: normalised image coordinates (for focal-unknown models, pixel coordinates divided
// by the model's focal lengths); d0[i], d1[i]: depth priors (NaN = none). `model` holds R and a
// translation direction t (any length). Triangulates every correspondence, fits
//   k * z0_i = d0_i + shift0,   k * z1_i = scale * (d1_i + shift1)
// by linear least squares over the points in front of both cameras, and rescales model->t by k.
// Each view is fitted separately from its own priors (d0 = k z0 - shift0, d1 = (k / scale) z1 -
// shift1, z from the unit-length translation). fit_shift = false fixes both shifts to 0 (the
// scale-only ablation). Needs >= 2 points with depth in each view; returns false (model
// untouched) otherwise, when the depths do not determine the fit, or when k or the scale is not
// positive. R, f0 and f1 are never changed.
bool FitAffineDepthToPose(const std::vector<Eigen::Vector2d>& x0, const std::vector<Eigen::Vector2d>& x1,
                          const std::vector<double>& d0, const std::vector<double>& d1, AffineDepthPose* model,
                          bool fit_shift = true);

// The same model fitted the other way round, for when the pose is final: the triangulated depths are regressed
// on the priors, k z0_i = d0_i + shift0 and k z1_i = scale (d1_i + shift1), by weighted least squares of the
// relative residuals with weights 1 / (prior_sigma^2 + (angular_noise / sin(ray angle))^2): the inverse of the
// variance of a prior's relative misfit plus that of the triangulated depth's relative error. Well-triangulated
// points count alike (as a fit against true depths would weigh them) and points near infinity hardly at all;
// Huber reweighting, iterated until the line settles, makes it robust to wrong triangulated depths (not to grossly
// wrong priors: they are the regressor). Priors are far less noisy than triangulated depths at small parallax, so
// regressing depths on priors does not dilute the slope as the other direction does.
// angular_noise: the matching noise in radians (pixel noise / focal length). max_shift0, max_shift1 (> 0): bounds of
// |shift0|, |shift1| in prior units; where a view's free line would be beyond its bound (or falls with the priors),
// each reweighting round takes the better of the two lines on the bound's edge, z = a (d +- max_shift) with a > 0.
// 0: unbounded. Same contract as FitAffineDepthToPose.
bool FitAffineDepthToPoseWeighted(const std::vector<Eigen::Vector2d>& x0, const std::vector<Eigen::Vector2d>& x1,
                                  const std::vector<double>& d0, const std::vector<double>& d1, double angular_noise,
                                  AffineDepthPose* model, bool fit_shift = true, double prior_sigma = 0.03,
                                  double max_shift0 = 0.0, double max_shift1 = 0.0);

}  // namespace madsfm
