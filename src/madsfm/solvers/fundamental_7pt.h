// 7-point fundamental matrix (Hartley & Zisserman, Sec. 11.1.2): at most 3 solutions.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace madsfm {

// p0[i], p1[i]: pixel coordinates (centred or not). Finds every real rank-2 F with
// [p1;1]^T F [p0;1] = 0 for the first 7 correspondences (unit Frobenius norm, arbitrary sign).
// Returns the count (<= 3); degenerate samples (rank-deficient 7x9 system, coincident or
// non-finite points, fewer than 7 correspondences) give 0. Coordinates are normalised internally.
int SolveFundamental7pt(const std::vector<Eigen::Vector2d>& p0, const std::vector<Eigen::Vector2d>& p1,
                        std::vector<Eigen::Matrix3d>* fundamentals);

}  // namespace madsfm
