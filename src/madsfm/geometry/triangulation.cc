#include "madsfm/geometry/triangulation.h"

#include <Eigen/Geometry>
#include <cmath>

namespace madsfm {

bool TriangulateDepths(const Eigen::Matrix3d& R, const Eigen::Vector3d& t, const Eigen::Vector2d& x0,
                       const Eigen::Vector2d& x1, double* depth0, double* depth1) {
  // In camera 1: depth0 * a + t = depth1 * b with a = R [x0;1], b = [x1;1]. Least squares over the
  // two depths: the closest points of the two rays (their mid-point is the triangulated point).
  const Eigen::Vector3d a = R * x0.homogeneous();
  const Eigen::Vector3d b = x1.homogeneous();
  // The normal equations [aa, -ab; ab, -bb] [d0; d1] = [-at; -bt] have determinant -|a x b|^2;
  // their solution, written with cross products (Binet-Cauchy) to avoid the cancellation of
  // aa * bb - ab^2 for small parallax:
  //   d0 = (b x t).(a x b) / |a x b|^2,   d1 = (a x t).(a x b) / |a x b|^2.
  const Eigen::Vector3d axb = a.cross(b);
  const double det = axb.squaredNorm();
  const double num0 = b.cross(t).dot(axb), num1 = a.cross(t).dot(axb);
  if (!std::isfinite(det) || !std::isfinite(num0) || !std::isfinite(num1)) return false;
  // det = aa * bb * sin^2(angle between the rays); rays within ~1e-7 rad of parallel carry no
  // depth information.
  if (!(det > 1e-14 * a.squaredNorm() * b.squaredNorm())) return false;
  *depth0 = num0 / det;
  *depth1 = num1 / det;
  return true;
}

}  // namespace madsfm
