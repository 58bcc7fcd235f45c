// Plane-induced homographies between two views: a linear fit to correspondences and the decomposition into
// rotation, translation and plane.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace madsfm {

// X1 = R X0 + T for points on the plane n^T X0 = d (unit normal n, distance d > 0) gives x1 ~ H x0 with
// H = R + (T / d) n^T, x0 and x1 normalised image coordinates.
struct PlanarPose {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();  // translation over the plane's distance from camera 0
  Eigen::Vector3d n = Eigen::Vector3d::Zero();  // unit plane normal in camera 0, pointing away from it
};

// Direct linear fit of x1 ~ H x0 to the correspondences `indices` (least squares of the algebraic error; the
// coordinates should be normalised, O(1)). Returns false for fewer than 4 correspondences or non-finite input.
bool FitHomographyLinear(const std::vector<Eigen::Vector2d>& x0, const std::vector<Eigen::Vector2d>& x1,
                         const std::vector<int>& indices, Eigen::Matrix3d* H);

// Distance in the image of view 1 between x1 and the transfer of x0 (infinite when x0 maps to infinity).
double HomographyTransferError(const Eigen::Matrix3d& H, const Eigen::Vector2d& x0, const Eigen::Vector2d& x1);

// The decompositions H ~ R + t n^T (t = T / d) (Ma, Soatto, Kosecka, Sastry, "An Invitation to 3-D Vision", sec. 5.3.3) that put
// the plane in front of camera 0 at the correspondences `indices` (n^T [x0; 1] > 0 for most of them): up to two
// (the planar twins; for pure rotation one, with t = 0). H may have any scale and sign.
std::vector<PlanarPose> DecomposeHomography(const Eigen::Matrix3d& H, const std::vector<Eigen::Vector2d>& x0,
                                            const std::vector<Eigen::Vector2d>& x1, const std::vector<int>& indices);

}  // namespace madsfm
