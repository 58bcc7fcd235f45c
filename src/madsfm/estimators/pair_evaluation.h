// Runs one estimator method on one pair directory and measures it against the ground truth; shared by
// `madsfm pair` and `madsfm bench`.
#pragma once

#include <limits>
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
  // Whether the pair determines the depth corrections, and their standard deviations (HybridEstimate).
  bool depth_observable = false;
  double sigma_scale = std::numeric_limits<double>::quiet_NaN();
  double sigma_shift0 = std::numeric_limits<double>::quiet_NaN();
  double sigma_shift1 = std::numeric_limits<double>::quiet_NaN();
  bool shifts_dropped = false;  // HybridEstimate::shifts_dropped (also a note)
  bool scale_reset = false;     // HybridEstimate::scale_reset (also a note)
  bool low_parallax_weighting = false;  // HybridEstimate::low_parallax_weighting
  double score = std::numeric_limits<double>::quiet_NaN();  // HybridEstimate::score
  // Focal modes: relative standard deviations of the focal lengths (HybridEstimate::sigma_focal0/1).
  double sigma_focal0 = std::numeric_limits<double>::quiet_NaN();
  double sigma_focal1 = std::numeric_limits<double>::quiet_NaN();
  int iterations = 0;
  double runtime_ms = 0.0;  // estimator only (not file reading)
  // Errors against T_0to1 / K when the pair has a ground truth; failures count as 180 deg and focal error 1.
  std::optional<double> rot_err_deg, trans_err_deg, focal_err;
  std::vector<std::string> notes;  // fallbacks taken, e.g. "no depth: point method"
  // Depth corrections against the true depth maps (pairs with gt_depth_*_file and T_0to1, successful estimates):
  // median relative error of the corrected priors at the true inliers after one common scale for both views
  // (the gauge), and the same for the best per-view affine fit of the priors to the true depths (the error no
  // estimator of this model can beat). See DepthCorrectionError.
  std::optional<double> depth_err, depth_err_oracle;
  std::optional<int> depth_support;  // true inliers with a prior and a true depth in both views
  bool absurd_shift = false;  // |shift0| or |shift1| above 10x the median prior depth of its view
  int seed = 0;               // the estimator seed of this run (bench)
};

struct DepthCorrectionError {
  int support = 0;         // true inliers used
  double estimate = 0.0;   // median |g z_hat / z - 1| over both views, g the least-squares gauge
  double oracle = 0.0;     // median |(a_i d + b_i) / z - 1| of the per-view relative least-squares affine fit
};

// Measures the corrected priors (model: z_hat0 = d0 + shift0, z_hat1 = scale (d1 + shift1)) against true
// depths z0 / z1 of the same matches (NaN where unknown). Only matches flagged in `use` count. Returns
// std::nullopt with fewer than 8 usable matches.
std::optional<DepthCorrectionError> MeasureDepthCorrection(const AffineDepthPose& model, const std::vector<double>& d0,
                                                           const std::vector<double>& d1, const std::vector<double>& z0,
                                                           const std::vector<double>& z1, const std::vector<char>& use);

// Samples the depth maps at the matches (NaN where invalid); returns the per-match priors.
void SamplePairDepths(const PairData& pair, std::vector<double>* d0, std::vector<double>* d1);

// The notes an estimate adds to `notes` (PairResult::notes, the Python result's notes): the scale-only fallback taken
// (shifts_dropped), a scale reset.
void AppendEstimateNotes(const HybridEstimate& estimate, std::vector<std::string>* notes);

// Runs `method` on the pair. In the focal modes only the principal points of K0 / K1 are used.
PairResult EvaluatePair(const PairData& pair, CameraMode mode, const std::string& method,
                        const HybridEstimatorOptions& base_options);

}  // namespace madsfm
