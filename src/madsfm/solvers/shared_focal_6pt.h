// 6-point relative pose with one unknown focal length shared by both views (Stewenius et al. 2008,
// "Solutions to minimal generalized relative pose problems"; polynomial-eigenvalue form of
// Kukelova et al. 2008): at most 15 solutions.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace madsfm {

struct FocalFundamental {
  Eigen::Matrix3d F;  // fundamental matrix in principal-point-centred pixel coordinates
  double f0 = 0.0;    // focal length of view 0 (pixels)
  double f1 = 0.0;    // focal length of view 1 (pixels); equal to f0 for the shared-focal solver
};

// p0[i], p1[i]: pixel coordinates minus the principal point. Finds every real (F, f) with
// [p1;1]^T F [p0;1] = 0 for the first 6 correspondences and E = K F K an essential matrix,
// K = diag(f, f, 1), f > 0. Returns the count (<= 15).
int SolveSharedFocal6pt(const std::vector<Eigen::Vector2d>& p0, const std::vector<Eigen::Vector2d>& p1,
                        std::vector<FocalFundamental>* solutions);

}  // namespace madsfm
