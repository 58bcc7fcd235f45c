// Options and results of the hybrid affine-depth LO-MSAC estimator (paper Sec. 4.4).
#pragma once

#include <cstdint>
#include <vector>

#include "madsfm/geometry/affine_depth_pose.h"

namespace madsfm {

// Which minimal solvers the RANSAC loop draws from (paper Table 6 ablation).
enum class SolverChoice {
  kHybrid,      // affine-depth solver and point solver, chosen by the inlier ratios of their data types
  kDepthOnly,   // the affine-depth solver only
  kPointsOnly,  // the point solver only (5pt / 6pt / 7pt + Bougnoux): the point-only baseline
};

// Which data types score hypotheses and enter the local optimisation.
enum class ScoringMode {
  kHybrid,            // reprojection 0->1, 1->0 and Sampson (the paper's hybrid MSAC score)
  kReprojectionOnly,  // depth-induced reprojection errors only (the paper's "non-hybrid" ablation)
  kSampsonOnly,       // Sampson error only (the classic point-only score)
};

struct HybridEstimatorOptions {
  // Inlier threshold tau_r of the depth-induced reprojection errors, pixels. The paper uses 8 px for
  // ~640x480 indoor images and 16 px for large / outdoor images.
  double reproj_threshold = 8.0;
  // Inlier threshold tau_s of the Sampson error, pixels. The paper: 2 px (ScanNet), 1 px otherwise.
  double epipolar_threshold = 2.0;
  // lambda_s: the Sampson term enters the score as 2 * lambda_s * (tau_r / tau_s)^2 * min(E_s, tau_s^2),
  // so that a Sampson outlier costs as much as an outlier in both reprojection directions.
  double sampson_weight = 1.0;

  SolverChoice solvers = SolverChoice::kHybrid;
  ScoringMode scoring = ScoringMode::kHybrid;
  // false: scale-only ablation (shift0 = shift1 = 0 in solvers, scoring and refinement).
  bool estimate_shift = true;

  // RANSAC iterations: at least min_iterations, then adaptive (hybrid stopping criterion of
  // Camposeco et al. 2018 at `confidence`), at most max_iterations.
  int min_iterations = 100;
  int max_iterations = 10000;
  double confidence = 0.9999;

  // Local optimisation (Lebeda et al. 2012): when a hypothesis beats the best so far, up to
  // num_lo_steps rounds of (joint least squares over the inliers of all data types, re-scoring).
  int num_lo_steps = 4;
  // Levenberg-Marquardt iterations per least-squares solve.
  int lo_max_lm_iterations = 10;
  // Final refinement on the inliers of the best model.
  bool final_refinement = true;
  int final_max_lm_iterations = 50;
  // Weight of the reprojection terms in a last refinement after the paper's joint one (1: none, the
  // paper's estimator). Below 1 the pose leans on the epipolar evidence; 0 (default) refines the pose
  // on the Sampson inliers only, with the focal lengths fixed at the joint estimate, and refits scale
  // and shifts to it. Monocular depth is biased (non-affine distortion) while good matches are not,
  // so this wins wherever the epipolar geometry is well conditioned; docs/benchmarks.md measures it.
  double final_reprojection_weight = 0.0;

  // Calibrated hybrid only: a point-only LO-MSAC run (5pt, Sampson score) competes with the hybrid
  // result; if it finds at least this many times the hybrid model's epipolar inliers, the depth priors
  // have dragged the hybrid model away from the epipolar evidence and the point model's pose is taken
  // (scale and shifts refitted). 0 disables the check. See docs/benchmarks.md.
  double epipolar_check_ratio = 1.05;

  // Seed of the random sampler: the same seed gives the same result.
  uint64_t seed = 0;

  // Throws std::invalid_argument naming the offending option.
  void Check() const;
};

struct HybridEstimate {
  bool success = false;
  // In the problem's solver units: focal lengths in pixels for the focal modes, 1 when calibrated.
  AffineDepthPose model;
  // Inlier masks over all correspondences per data type: reprojection 0->1, 1->0, Sampson.
  std::vector<char> inliers_reproj0, inliers_reproj1, inliers_sampson;
  int num_inliers_reproj0 = 0, num_inliers_reproj1 = 0, num_inliers_sampson = 0;
  double score = 0.0;  // MSAC score of the model (lower is better)
  int iterations = 0;
  int num_lo = 0;
  int num_depth_samples = 0, num_point_samples = 0;  // minimal samples drawn per solver
  bool epipolar_check_switched = false;  // the point-only competitor won (epipolar_check_ratio)
  double runtime_ms = 0.0;
};

}  // namespace madsfm
