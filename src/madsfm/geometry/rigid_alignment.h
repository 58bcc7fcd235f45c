// Least-squares alignment of two corresponding 3-D point sets.
#pragma once

#include <Eigen/Core>

namespace madsfm {

// Finds the rotation R and translation t minimising sum_i ||q_i - (R p_i + t)||^2 (Kabsch, with
// the reflection fix). Needs n >= 3 points not all collinear; returns false (outputs untouched)
// for degenerate or non-finite input.
bool AlignRigid(const Eigen::Vector3d* p, const Eigen::Vector3d* q, int n, Eigen::Matrix3d* R, Eigen::Vector3d* t);

// Finds s > 0, R, t minimising sum_i ||q_i - (s R p_i + t)||^2 (Umeyama). Same conditions.
bool AlignSimilarity(const Eigen::Vector3d* p, const Eigen::Vector3d* q, int n, double* s, Eigen::Matrix3d* R,
                     Eigen::Vector3d* t);

}  // namespace madsfm
