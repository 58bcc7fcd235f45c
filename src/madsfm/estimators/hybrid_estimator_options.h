// Options and results of the hybrid affine-depth LO-MSAC estimator (paper Sec. 4.4).
#pragma once

#include <cstdint>
#include <limits>
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
  // Sampson data whose triangulated point lies behind a camera count as outliers (as the paper's code scores
  // them): the Sampson error alone cannot tell the twisted-pair and sign-flipped poses apart.
  bool sampson_cheirality = true;
  // ... judged only where the two rays are further apart than this many times the angle of the Sampson threshold
  // (epipolar_threshold / focal in pixels, at least ~0.06 deg): an inlier's rays may be that far off, so at smaller
  // parallax the sign of its depth is noise (low-parallax pairs, far points). 0: the fixed 0.06 deg alone.
  // 0.5 on the development sets (docs/benchmarks.md section 11); 1.0 gained more on low parallax but lost a
  // planar pair of the point-only planar test.
  double cheirality_min_parallax = 0.5;

  // RANSAC iterations: at least min_iterations, then adaptive (hybrid stopping criterion of
  // Camposeco et al. 2018 at `confidence`), at most max_iterations.
  int min_iterations = 100;
  // At least this many when only point samples are drawn in two-focal mode (7-point fundamental matrix and
  // Bougnoux's focal lengths: no depth solver, or too few matches with depth). A clean 7-point sample often gives
  // focal lengths far off where they are weakly determined, and after local optimisation a wrong-focal basin
  // that holds ~95% of the inliers, so the stopping criterion, which trusts any clean sample, ends too early. 1000
  // as PoseLib's examples: two-focal points AUC@10 +1.5 on average over the rendered and synthetic sets
  // (docs/benchmarks.md section 11, "Update 2026-12-02 (evening)"). Capped by max_iterations.
  int min_iterations_two_focal_points = 1000;
  // The same for one shared focal length with point samples only (6-point solver: `--method points`, or a pair without
  // depth). Clean 6-point samples end in a wrong-focal basin that holds ~98% of the inliers often enough that the
  // adaptive stop, reached after min_iterations at such inlier ratios, leaves 1 run in 10 far off on some pairs. 300:
  // rendered pairs at 0.5 px, 10 seeds, AUC@10 92.82 -> 93.28 with the seed spread 0.63 -> 0.26, and the synthetic
  // shared-focal sets over 30 seeds (docs/benchmarks.md section 11, update of 2026-12-07, midday). Capped by
  // max_iterations.
  int min_iterations_shared_focal_points = 300;
  int max_iterations = 10000;
  double confidence = 0.9999;
  // Problems with a guide (RelposeProblem::guided, e.g. the matches COLMAP's geometric verification kept): this
  // fraction of the minimal samples is drawn from the guided correspondences, the rest from all of them, and the
  // stopping criterion counts both kinds of draw with their own inlier ratios. Where the guide holds mostly inliers
  // the search stops after min_iterations however many outliers the raw matches carry; where it does not, its
  // samples fail and the uniform ones carry the search (at most 1 / (1 - fraction) times the iterations). 0:
  // uniform sampling only. Without a guide the option has no effect (docs/benchmarks.md section 9).
  double guided_sampling_fraction = 0.9;

  // Local optimisation (Lebeda et al. 2012, LO+ as in RansacLib): when a hypothesis beats the best so far, a
  // joint least-squares fit over its inliers under thresholds relaxed by lo_threshold_multiplier (on the squared
  // thresholds), then num_lo_steps rounds of (least squares on a random subset of lo_inner_sample_multiplier x the
  // minimal sample size of those inliers, then num_lo_lsq_steps fits on random subsets of lo_lsq_sample_size of
  // the inliers under thresholds shrinking from the relaxed to the true ones). 0 rounds: only the first fit.
  int num_lo_steps = 4;
  int num_lo_lsq_steps = 4;
  double lo_threshold_multiplier = 5.0;
  int lo_inner_sample_multiplier = 3;
  int lo_lsq_sample_size = 300;
  // The first fit of the local optimisation (least squares on all inliers under the relaxed thresholds) takes a random
  // subset of at most this many of their residual terms (reprojection in either view and Sampson, pooled as the later
  // subset fits pool them). Over 20 synthetic sets x 10 seeds x 3 seed offsets, 1000 raised AUC@10
  // summed over the sets by 5.1 (14 of 20 sets higher, all four low-parallax sets among them) and was 0-5% faster
  // (docs/benchmarks.md section 11, update of 2026-12-07, evening).
  // 0: all of them.
  int lo_first_fit_sample_size = 1000;
  // RANSAC iterations before the first local optimisation (Lebeda et al.: early best models change too often to
  // be worth optimising); the best model so far is optimised when they are reached.
  int lo_starting_iterations = 50;
  // A minimal model of another basin than the best model (DistinctModels: rotation > 1 deg or translation direction
  // > 5 deg apart) is locally optimised too when it scores within this fraction of the best minimal model and better
  // than every such model before (0: off). Minimal models of the right basin can score a few percent worse than a
  // lucky one of a wrong basin (far points, noisy samples) and would otherwise never be optimised.
  double alt_basin_lo_margin = 0.05;
  // A new best minimal model is not locally optimised when it scores no better than the optimised best model and lies
  // in its basin (not DistinctModels): its optimisation would end where the best already is. Over 20 synthetic sets x
  // 10 seeds x 3 seed offsets it changed AUC@10 by -0.08 summed over the sets (every set within its seed spread) and
  // cut the median time per pair by 8% (docs/benchmarks.md section 11, update of 2026-12-06, morning). false: every
  // new best minimal model is optimised (LO+).
  bool lo_skip_same_basin = true;
  // Point method (Sampson-only score), after the search: where at least this fraction of the best model's epipolar
  // inliers fit one plane-induced homography (within 2x epipolar_threshold) seen with a baseline of at least 5% of the
  // plane's distance, the other decomposition of that homography (the planar twin: both explain every point of the
  // plane, only the points off it decide) is locally optimised too and competes with the best (0: off). A search can
  // end in the twin's basin when its minimal models happen to score better there. The hybrid score needs no such step:
  // the depth priors tell the twins apart (docs/benchmarks.md section 11).
  double planar_twin_min_support = 0.5;
  // Low parallax: where the search's best model, after the first local optimisation, transfers its epipolar inliers by
  // a rotation alone to within a median of low_parallax_noise_ratio times their noise level (1.4826 x their median
  // absolute Sampson error), the Sampson term's weight lambda_s is multiplied by low_parallax_sampson_factor for the
  // rest of the search, the local optimisation and the last refinement. The epipolar error then hardly constrains the
  // direction of the translation, and its noise outweighs the depth priors, which do. Measured over 20 synthetic sets
  // x 10 seeds x 3 seed offsets and a second generator's rendered pairs (docs/benchmarks.md section 11, update of
  // 2026-12-06, evening): a factor of 0.35 for every pair raised the four low-parallax sets by 4-6 AUC@10 but lowered
  // others by up to 2 and the example pairs' focal modes; taken at low parallax only, it keeps the gain.
  // HybridEstimate::score stays the MSAC score under sampson_weight. 1: off.
  double low_parallax_sampson_factor = 0.35;
  double low_parallax_noise_ratio = 6.0;
  // Pairs where that switch was taken: the last refinement's reprojection weight (final_reprojection_weight elsewhere),
  // with the focal lengths held fixed in the focal modes. The epipolar-only refinement lets the translation's
  // direction slide along the flat epipolar cost of a small baseline. 0.3 raised the synthetic low-parallax calibrated
  // sets by 0.6-1.0 AUC@10 and rendered low-parallax pairs with real SIFT by 6.5 (0.05 px) and 8.6 (0.2 px noise);
  // in shared focal +0.5 to +0.8 (synthetic) and +6.6 (rendered, 0.2 px), for -1.0 on dev planar shared focal
  // (docs/benchmarks.md section 11, updates of 2026-12-07). Set it to final_reprojection_weight for off.
  double low_parallax_final_reprojection_weight = 0.3;
  // After that mixed last refinement, the depth corrections start from the fit of the priors to the triangulated
  // epipolar inliers (true), not from the joint refinement's scale and shifts (false), which drift along the flat
  // directions of a small baseline. Held-out low parallax calibrated, 30 seeds: within 1.25x of the oracle's error in
  // 46.0% of runs against 41.2% (docs/benchmarks.md section 11, updates of 2026-12-07 (later) and (evening)).
  bool mixed_refinement_depth_from_triangulation = true;
  // Levenberg-Marquardt iterations per least-squares fit of the local optimisation; two focal lengths (11 free
  // parameters, a focal direction the subsets determine poorly) get lo_max_lm_iterations_two_focal. Over 20 synthetic
  // sets x 10 seeds x 3 seed offsets, 6 instead of 10 left the calibrated and shared-focal sets unchanged (+0.17 AUC@10
  // summed over 16 sets, every set within its seed spread) and cut the local optimisation's time; on the four
  // two-focal sets it cost 3.0 (docs/benchmarks.md section 11, update of 2026-12-06).
  int lo_max_lm_iterations = 6;
  int lo_max_lm_iterations_two_focal = 10;
  // Final refinement on the inliers of the best model.
  bool final_refinement = true;
  int final_max_lm_iterations = 50;
  // Weight of the reprojection terms in a last refinement after the paper's joint one (1: none, the
  // paper's estimator). Below 1 the pose leans on the epipolar evidence; 0 (default) refines the pose
  // on the Sampson inliers only, with the focal lengths fixed at the joint estimate, and refits scale
  // and shifts to it. Monocular depth is biased (non-affine distortion) while good matches are not,
  // so this wins wherever the epipolar geometry is well conditioned; docs/benchmarks.md measures it.
  double final_reprojection_weight = 0.0;
  // Focal modes, before that last refinement: the focal lengths (and pose) of the epipolar inliers alone are taken
  // where their relative Gauss-Newton standard deviation is at most this and they reject the joint ones (differ by
  // more than 3 deviations) (0: never; Engine::TakeEpipolarFocal; docs/benchmarks.md section 11). Two focal lengths
  // are not taken where a view would keep less than half of its depth inliers (optical axes that meet leave them to
  // the priors).
  double epipolar_focal_max_sigma = 0.01;
  // Shared focal only: also where their relative deviation is at most this (above epipolar_focal_max_sigma) and they
  // reject the joint focal length by more than 5 deviations. Forward motion leaves the joint focal to the depth priors,
  // whose non-affine distortion then moves it by 5-100% while its own deviation stays below 1%; the epipolar one,
  // 2-4% precise there, rejects it (docs/benchmarks.md section 11). Not for two focal lengths: there it lost accuracy
  // on the sweep (0: off).
  double epipolar_focal_wide_sigma = 0.05;
  // That last refinement's loss (and, for the point method, a last refinement of pose and focal lengths on the
  // epipolar inliers): Cauchy with a scale of this times the inliers' robust noise level (1.4826 x their median
  // absolute Sampson residual), so that mislocalised matches the threshold still admits pull less than under least
  // squares, while uniformly noisy matches get a scale near the threshold; 0: least squares (docs/benchmarks.md
  // section 11).
  double final_cauchy_ratio = 2.0;

  // Calibrated hybrid only: a point-only LO-MSAC run (5pt, Sampson score) competes with the hybrid
  // result; if it finds at least this many times the hybrid model's epipolar inliers, the depth priors
  // have dragged the hybrid model away from the epipolar evidence and the point model's pose is taken
  // (scale and shifts refitted). 0 disables the check (the default: with the LO over inlier subsets and the
  // cheirality of Sampson data it changed no result on the hard_* presets nor on the example pairs, and it
  // doubles the cost of a calibrated pair; docs/benchmarks.md).
  double epipolar_check_ratio = 0.0;

  // Hybrid: a result with depth inliers below 5% of its epipolar inliers, on a pair where most matches have priors,
  // is searched once more with a seed derived from `seed`; the lower score wins (on the held-out hard pairs every such
  // result was a wrong basin; docs/benchmarks.md section 11).
  bool retry_depth_less = true;
  // Hybrid with shifts: a result whose depth corrections the priors do not determine (depth_observable false) on a
  // pair where most matches have priors is estimated again with the scale-only model (estimate_shift false, same
  // seed), which replaces it when it succeeds with an MSAC score at most as high (HybridEstimate::shifts_dropped;
  // still not depth_observable). Two free shifts let the pose slide along a flat valley where nothing pins them
  // (small baselines, one dominant plane); the simpler model then fits as well. docs/benchmarks.md section 11
  // (update of 2026-12-03 evening).
  bool scale_only_fallback = true;

  // Bound of the shifts: |shift_i| <= max_shift_ratio x the median prior of view i (0: unbounded). A shift of many
  // times the depths themselves flattens the corrected depth map; it only ever appears where the depths are not
  // determined. It holds for every model: depth-solver models beyond it are not scored, depth fits beyond it fall
  // back to the scale-only fit (the final regression to the bound's edge, depth_fit_regression_in_bound), and
  // refinement steps beyond it are rejected.
  double max_shift_ratio = 5.0;
  // After the pose is final: fit scale, shifts and |t| to it by least squares of the depth inliers' reprojection
  // errors (R and the direction of t fixed), kept when the score does not get worse.
  bool final_depth_fit = true;
  // Then regress the triangulated epipolar inliers on their priors (weights that count well-triangulated points
  // alike) and take that fit when it keeps >= 90% of the depth inliers: pixel residuals weigh near points far
  // more than far ones, so the least-squares corrections fit the near surfaces only.
  bool depth_fit_regression = true;
  // ... also after the low-parallax switch (HybridEstimate::low_parallax_weighting). Off: there the triangulated
  // depths are too noisy to regress on and the least-squares fit of the reprojection errors is closer to the truth
  // (docs/benchmarks.md section 11, update of 2026-12-07, night).
  bool low_parallax_depth_fit_regression = false;
  // Where that regression's shift of a view would be beyond max_shift_ratio, it is fitted within the bound (the best
  // line on the bound's edge, still subject to the 90% rule) instead of being discarded. The best affine fit of a prior
  // that hardly correlates with the truth is nearly flat, with a large shift; the edge keeps most of its benefit
  // (held-out planar shared focal: within 1.25x of the oracle 60.4% -> 73.4%; docs/benchmarks.md section 11, update
  // of 2026-12-07, late night).
  bool depth_fit_regression_in_bound = true;
  // Focal modes: the depth corrections (scale, shifts and |t|) are fitted to the joint estimate, the pose and focal
  // lengths that the depth priors and the matches agreed on, before the last epipolar-only refinement moves the pose
  // with the focal lengths held. Triangulating with a pose and focal lengths that were not estimated together distorts
  // the far depths (outdoor shared focal: within 1.25x of the oracle 50% -> 64% development, 58% -> 70% held-out;
  // docs/benchmarks.md section 11, update of 2026-12-08). The output keeps the refined pose, its focal lengths and its
  // epipolar inliers. Not where TakeEpipolarFocal replaced the joint focal lengths (the epipolar evidence rejected
  // them), not after the low-parallax switch (its mixed last refinement takes them from the triangulation fit), nor
  // in the calibrated mode, where the refined pose with the known focal lengths is the better one.
  bool focal_depth_from_joint = true;
  // The depth corrections count as observable (HybridEstimate::depth_observable) when the standard deviations of
  // shift0 / shift1 (relative to the median prior) and of the scale (relative) are at most this.
  double max_depth_sigma = 0.1;

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
  // MSAC score of the model (lower is better). With focal_depth_from_joint in effect, that of its pose and focal
  // lengths with the depth corrections fitted to them: what the comparisons between searches weigh.
  double score = 0.0;
  int iterations = 0;
  int num_lo = 0;
  int num_depth_samples = 0, num_point_samples = 0;  // minimal samples drawn per solver
  bool epipolar_check_switched = false;  // the point-only competitor won (epipolar_check_ratio)
  // The search ran with the low-parallax Sampson weight (low_parallax_sampson_factor).
  bool low_parallax_weighting = false;
  // The best model of another basin found by the search within 1% of the best score, after the same final refinement
  // (infinity: none), and
  // whether it then scored lower than the search's best and replaced it.
  double runner_up_score = std::numeric_limits<double>::infinity();
  bool runner_up_won = false;
  // Standard deviations of the depth corrections from the final depth fit (shifts relative to the median prior of
  // their view, scale relative to itself; NaN when not estimated), and whether they are all below
  // options.max_depth_sigma: false means the priors do not determine scale and shifts (tiny baseline, pure
  // rotation, too few depth inliers) and the reported values are not to be trusted. Without shifts
  // (estimate_shift = false) their sigmas stay NaN and the scale's decides, and the flag is also false when the
  // epipolar inliers show no parallax (a rotation alone transfers them to within 3x their noise level): there the
  // priors' own errors set the scale, which no standard deviation shows.
  double sigma_shift0 = std::numeric_limits<double>::quiet_NaN();
  double sigma_shift1 = std::numeric_limits<double>::quiet_NaN();
  double sigma_scale = std::numeric_limits<double>::quiet_NaN();
  bool depth_observable = false;
  // The fitted scale left [1/1000, 1000] x the ratio of the two views' median priors (it drifts to 0 or infinity
  // where nothing determines it, e.g. a pure rotation): it was replaced by that ratio, and depth_observable is false.
  bool scale_reset = false;
  // The result with shifts had undetermined depth corrections and is the scale-only search's (scale_only_fallback):
  // shifts are 0 with NaN sigmas, and depth_observable stays false (the shifts were assumed, not measured).
  bool shifts_dropped = false;
  // Focal modes: relative standard deviations of f0 and f1 at the final model, pose, scale and shifts free (the
  // marginal Gauss-Newton ones; shared focal: both the same); NaN when calibrated or not computable. Large where
  // the data leave the focal length open (small baselines with little rotation, forward motion).
  double sigma_focal0 = std::numeric_limits<double>::quiet_NaN();
  double sigma_focal1 = std::numeric_limits<double>::quiet_NaN();
  double runtime_ms = 0.0;
};

}  // namespace madsfm
