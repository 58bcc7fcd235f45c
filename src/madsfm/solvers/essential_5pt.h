// Calibrated 5-point relative pose (Nister 2004, "An efficient solution to the five-point relative
// pose problem"; Stewenius et al. 2006): at most 10 essential matrices.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace madsfm {

// x0[i], x1[i]: normalised image coordinates. Finds every real essential matrix E (unit Frobenius
// norm) with [x1;1]^T E [x0;1] = 0 for the first 5 correspondences. Returns the count (<= 10).
int SolveEssential5pt(const std::vector<Eigen::Vector2d>& x0, const std::vector<Eigen::Vector2d>& x1,
                      std::vector<Eigen::Matrix3d>* essentials);

}  // namespace madsfm
