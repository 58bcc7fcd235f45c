// Runs one estimator method on one pair directory and measures it against the ground truth; shared by
// `madsfm pair` and `madsfm bench`.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "madsfm/estimators/estimate_relpose.h"
#include "madsfm/io/pair_directory.h"

namespace madsfm {

// Method names accepted by the commands:
//   hybrid      the paper's estimator (affine-depth + point solver, hybrid score)
//   points      point-only baseline (5pt / 6pt / 7pt + Bougnoux, Sampson score) on the same engine
//   depth_only  affine-depth solver only, reprojection score only (the paper's "non-hybrid" ablation)
//   no_shift    hybrid with scale-only depth correction (the paper's shift ablation)
//   sampson_score  hybrid solvers with the Sampson score only (score ablation)
// Throws std::invalid_argument for another name.
HybridEstimatorOptions OptionsForMethod(const std::string& method, const HybridEstimatorOptions& base);
const std::vector<std::string>& MethodNames();

struct PairResult {
  std::string pair;
  std::string method;
  std::string camera_mode;
  bool success = false;
  AffineDepthPose model;  // focal lengths in pixels
  int num_matches = 0;
  int num_with_depth = 0;  // matches with a valid prior in both views
  int num_inliers_reproj0 = 0, num_inliers_reproj1 = 0, num_inliers_sampson = 0;
  int iterations = 0;
  double runtime_ms = 0.0;  // estimator only (not file reading)
  // Errors against T_0to1 / K when the pair has a ground truth; failures count as 180 deg and focal error 1.
  std::optional<double> rot_err_deg, trans_err_deg, focal_err;
  std::vector<std::string> notes;  // fallbacks taken, e.g. "no depth: point method"
};

// Samples the depth maps at the matches (NaN where invalid); returns the per-match priors.
void SamplePairDepths(const PairData& pair, std::vector<double>* d0, std::vector<double>* d1);

// Runs `method` on the pair. In the focal modes only the principal points of K0 / K1 are used.
PairResult EvaluatePair(const PairData& pair, CameraMode mode, const std::string& method,
                        const HybridEstimatorOptions& base_options);

}  // namespace madsfm
