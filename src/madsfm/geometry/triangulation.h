// Two-view triangulation.
#pragma once

#include <Eigen/Core>

namespace madsfm {

// Triangulates the correspondence x0 <-> x1 (normalised coordinates) for X1 = R X0 + t by the
// optimal mid-point of the two rays (least squares over the two depths). Writes the depth of the
// point in camera 0 and in camera 1. Returns false when the rays are (near) parallel or the input
// is not finite; depths may be negative (point behind a camera), callers check cheirality.
bool TriangulateDepths(const Eigen::Matrix3d& R, const Eigen::Vector3d& t, const Eigen::Vector2d& x0,
                       const Eigen::Vector2d& x1, double* depth0, double* depth1);

}  // namespace madsfm
