#include "madsfm/estimators/estimate_relpose.h"

#include <cmath>

#include "madsfm/estimators/hybrid_lo_msac.h"

namespace madsfm {

HybridEstimate EstimateRelativePose(CameraMode mode, const std::vector<Eigen::Vector2d>& p0,
                                    const std::vector<Eigen::Vector2d>& p1, const std::vector<double>& d0,
                                    const std::vector<double>& d1, const PinholeCamera& camera0,
                                    const PinholeCamera& camera1, const HybridEstimatorOptions& options,
                                    double max_image_dim) {
  RelposeProblem problem = MakeRelposeProblem(mode, p0, p1, d0, d1, camera0, camera1);
  if (max_image_dim > 0.0) {
    problem.min_focal = 0.1 * max_image_dim;
    problem.max_focal = 10.0 * max_image_dim;
  }
  HybridEstimate estimate = EstimateHybridRelpose(problem, options);
  if (mode == CameraMode::kCalibrated) {
    estimate.model.f0 = std::sqrt(camera0.fx * camera0.fy);
    estimate.model.f1 = std::sqrt(camera1.fx * camera1.fy);
  }
  return estimate;
}

HybridEstimatorOptions PointOnlyOptions(const HybridEstimatorOptions& base) {
  HybridEstimatorOptions o = base;
  o.solvers = SolverChoice::kPointsOnly;
  o.scoring = ScoringMode::kSampsonOnly;
  return o;
}

}  // namespace madsfm
