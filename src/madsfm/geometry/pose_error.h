// Pose-error metrics of design.md section 5 (as in the paper and SuperGlue-style evaluations).
#pragma once

#include <Eigen/Core>
#include <vector>

namespace madsfm {

// Angle of R_est * R_gt^T in degrees.
double RotationErrorDeg(const Eigen::Matrix3d& R_est, const Eigen::Matrix3d& R_gt);

// Angle theta between t_est and t_gt in degrees, reported as min(theta, 180 - theta). A zero or
// non-finite vector gives 180 (counted as a failure).
double TranslationErrorDeg(const Eigen::Vector3d& t_est, const Eigen::Vector3d& t_gt);

// Area under the recall curve of `errors` (degrees) up to each threshold, in [0, 1] (trapezoid
// over the sorted errors, as in SuperGlue / the paper's evaluation): recall (i + 1) / n at the
// i-th sorted error, the curve starts at (0, 0) and stays flat from the last error below the
// threshold up to the threshold. Errors equal to the threshold do not count; NaN or negative
// errors count as failures. Empty errors or a non-positive threshold give 0.
std::vector<double> PoseAuc(std::vector<double> errors, const std::vector<double>& thresholds);

}  // namespace madsfm
