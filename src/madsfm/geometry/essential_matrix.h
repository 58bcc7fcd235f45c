// Essential / fundamental matrix helpers and the Sampson error.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace madsfm {

// [t]_x
Eigen::Matrix3d CrossProductMatrix(const Eigen::Vector3d& t);

// E = [t]_x R for X1 = R X0 + t.
Eigen::Matrix3d EssentialFromPose(const Eigen::Matrix3d& R, const Eigen::Vector3d& t);

// The two rotations and the unit translation (up to sign) of an essential matrix.
void DecomposeEssential(const Eigen::Matrix3d& E, Eigen::Matrix3d* R1, Eigen::Matrix3d* R2, Eigen::Vector3d* t);

// Picks, among the 4 decompositions of E, the one that puts the most of the given correspondences
// (normalised coordinates) in front of both cameras. t has unit norm. Returns false when no
// decomposition has any point in front.
bool PoseFromEssential(const Eigen::Matrix3d& E, const std::vector<Eigen::Vector2d>& x0,
                       const std::vector<Eigen::Vector2d>& x1, Eigen::Matrix3d* R, Eigen::Vector3d* t);

// F = K1^-T E K0^-1.
Eigen::Matrix3d FundamentalFromEssential(const Eigen::Matrix3d& E, const Eigen::Matrix3d& K0,
                                         const Eigen::Matrix3d& K1);

// Squared Sampson error of the correspondence (p0, p1) under [p1;1]^T F [p0;1] = 0, in the units
// of p (squared).
inline double SampsonErrorSquared(const Eigen::Matrix3d& F, const Eigen::Vector2d& p0, const Eigen::Vector2d& p1) {
  const Eigen::Vector3d Fx0 = F * p0.homogeneous();
  const Eigen::Vector3d Ftx1 = F.transpose() * p1.homogeneous();
  const double c = p1.homogeneous().dot(Fx0);
  const double denom = Fx0.head<2>().squaredNorm() + Ftx1.head<2>().squaredNorm();
  return denom > 0.0 ? c * c / denom : 0.0;
}

// Bougnoux's focal lengths from a fundamental matrix given in principal-point-centred pixel
// coordinates ([p1;1]^T F [p0;1] = 0). Returns false (f0, f1 untouched) unless both squared
// focals are positive and finite; the formula is degenerate (0 / 0) when the two optical axes
// are coplanar, e.g. for parallel axes.
bool BougnouxFocals(const Eigen::Matrix3d& F, double* f0, double* f1);

}  // namespace madsfm
