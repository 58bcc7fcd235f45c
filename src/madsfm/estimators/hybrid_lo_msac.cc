#include "madsfm/estimators/hybrid_lo_msac.h"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <chrono>
#include <cmath>
#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "madsfm/estimators/hybrid_sampling.h"
#include "madsfm/estimators/minimal_solvers.h"
#include "madsfm/estimators/msac_scoring.h"
#include "madsfm/geometry/homography.h"
#include "madsfm/refinement/relpose_refiner.h"

namespace madsfm {
namespace {

// Bound of the fitted scale around the ratio of the views' median priors (HybridEstimate::scale_reset).
constexpr double kMaxScaleRatio = 1000.0;

// The refinements stop when an iteration lowers the cost by less than this fraction (the refiner's default, 1e-10,
// spent the last iterations of the final refinements on changes far below the noise). Measured on the 20 hard_*
// sets x 10 seeds x 3 seed offsets: AUC@10 summed -0.14 (no set moved by more than 0.12) for 11% less time on low
// parallax calibrated; 1e-5 saved 20% but lost 0.54 on one set (docs/benchmarks.md section 11, update of
// 2026-12-07 (later)).
constexpr double kRefinementFunctionTolerance = 1e-7;

// Two focal: the epipolar focal lengths (Engine::TakeEpipolarFocal) are not taken when a view would keep less than
// this share of its depth inliers.
constexpr double kTwoFocalEpipolarMinDepthShare = 0.5;

// The planar twin is only tried where the baseline is at least this fraction of the plane's distance from camera 0
// (the |t| of the twin's decomposition of the homography). Below it both decompositions differ little in rotation, the
// points off the plane barely tell them apart, and on the low-parallax sets the twin changed results both ways (the
// sweep of docs/benchmarks.md section 11, update of 2026-12-05 afternoon).
constexpr double kMinPlanarTwinBaseline = 0.05;

// Inlier ratios of the data types that drive the solver probabilities.
struct InlierRatios {
  double both_depths = 0.0;  // correspondences with both priors that are inliers of both reprojection types
  double sampson = 0.0;
};

InlierRatios ComputeRatios(const RelposeProblem& p, const InlierSets& in, const MsacWeights& w) {
  InlierRatios r;
  if (!p.with_both_depths.empty() && w.use_reprojection) {
    // Both sets are sorted: count the intersection restricted to correspondences with both priors.
    size_t a = 0, b = 0;
    int both = 0;
    while (a < in.reproj0.size() && b < in.reproj1.size()) {
      if (in.reproj0[a] < in.reproj1[b]) ++a;
      else if (in.reproj0[a] > in.reproj1[b]) ++b;
      else { ++both; ++a; ++b; }
    }
    r.both_depths = static_cast<double>(both) / p.with_both_depths.size();
  }
  if (p.size() > 0 && w.use_sampson) r.sampson = static_cast<double>(in.sampson.size()) / p.size();
  if (!w.use_sampson) r.sampson = r.both_depths;
  if (!w.use_reprojection) r.both_depths = r.sampson;
  return r;
}

// The same ratios within the guided correspondences (mask over all of them; num_guided of them, num_guided_depth
// with both priors).
InlierRatios ComputeGuidedRatios(const InlierSets& in, const MsacWeights& w, const std::vector<char>& mask,
                                 int num_guided, int num_guided_depth) {
  InlierRatios r;
  if (num_guided_depth > 0 && w.use_reprojection) {
    size_t a = 0, b = 0;
    int both = 0;
    while (a < in.reproj0.size() && b < in.reproj1.size()) {
      if (in.reproj0[a] < in.reproj1[b]) ++a;
      else if (in.reproj0[a] > in.reproj1[b]) ++b;
      else { both += mask[in.reproj0[a]]; ++a; ++b; }
    }
    r.both_depths = static_cast<double>(both) / num_guided_depth;
  }
  if (num_guided > 0 && w.use_sampson) {
    int c = 0;
    for (int i : in.sampson) c += mask[i];
    r.sampson = static_cast<double>(c) / num_guided;
  }
  if (!w.use_sampson) r.sampson = r.both_depths;
  if (!w.use_reprojection) r.both_depths = r.sampson;
  return r;
}

// The element at index size / 2 of the sorted values (the upper median); v must not be empty.
double UpperMedian(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

double MedianPrior(const std::vector<double>& d, const std::vector<int>& valid) {
  if (valid.empty()) return 1.0;
  std::vector<double> v;
  v.reserve(valid.size());
  for (int i : valid) v.push_back(d[i]);
  const double m = UpperMedian(std::move(v));
  return m > 0.0 ? m : 1.0;
}

// Whether two models lie in different basins of the score: rotations more than 1 deg apart, or translation directions
// more than 5 deg apart.
// Cosines of the angle between two rotations and between two translation directions (1 when a translation is 0).
struct PoseCosines {
  double rotation, translation;
};
PoseCosines CosinesBetween(const Eigen::Matrix3d& Ra, const Eigen::Vector3d& ta, const Eigen::Matrix3d& Rb,
                           const Eigen::Vector3d& tb) {
  const double na = ta.norm(), nb = tb.norm();
  return {std::clamp(0.5 * ((Ra.transpose() * Rb).trace() - 1.0), -1.0, 1.0),
          na > 0.0 && nb > 0.0 ? std::clamp(ta.dot(tb) / (na * nb), -1.0, 1.0) : 1.0};
}

bool DistinctModels(const AffineDepthPose& a, const AffineDepthPose& b) {
  const PoseCosines c = CosinesBetween(a.R, a.t, b.R, b.t);
  return c.rotation < std::cos(1.0 * M_PI / 180.0) || c.translation < std::cos(5.0 * M_PI / 180.0);
}

class Engine {
 public:
  Engine(const RelposeProblem& p, const HybridEstimatorOptions& o)
      : p_(p), o_(o), w_(MsacWeights::FromOptions(o)), solvers_(p, o.estimate_shift), sampler_(o.seed) {
    median_prior0_ = MedianPrior(p.d0, p.with_depth0);
    median_prior1_ = MedianPrior(p.d1, p.with_depth1);
    if (o.guided_sampling_fraction > 0.0 && !p.guided.empty()) {
      guided_mask_.assign(p.size(), 0);
      for (int i : p.guided) guided_mask_[i] = 1;
      for (int i : p.with_both_depths) {
        if (guided_mask_[i]) guided_depth_.push_back(i);
      }
    }
  }

  HybridEstimate Run();

 private:
  void LocalOptimize(AffineDepthPose* model, double* score, bool from_point_solver);
  void DrawSubset(const InlierSets& in, int k, InlierSets* out);
  RelposeRefinerOptions RefinerOptions(int max_iterations) const;
  bool Refine(AffineDepthPose* model, const InlierSets& inliers, int max_iterations);
  void FitDepthCorrections(AffineDepthPose* model, double* score, HybridEstimate* result);
  void LeanOnEpipolarEvidence(double reprojection_weight, bool refine_focal, AffineDepthPose* model, double* score);
  void TakeEpipolarFocal(AffineDepthPose* model, double* score);
  void DepthCorrectionsOfJointEstimate(AffineDepthPose joint, const InlierSets& joint_inliers, double joint_score,
                                       AffineDepthPose* model, HybridEstimate* result);
  void FocalSigmas(const AffineDepthPose& model, HybridEstimate* result) const;
  double ParallaxPixels(const AffineDepthPose& model) const;
  bool ParallaxMeasurable(const AffineDepthPose& model) const;
  bool LowerSampsonWeightAtLowParallax(const AffineDepthPose& best);
  double SampsonNoiseLevel(const AffineDepthPose& model, double sampson_weight) const;
  double FinalCauchyScale(const AffineDepthPose& model) const;
  void RobustPointRefinement(AffineDepthPose* model, double* score);
  bool KeepIfEpipolarInliersRemain(const AffineDepthPose& refined, AffineDepthPose* model, double* score,
                                   double min_depth_share = 0.0);
  bool ShiftsInBound(const AffineDepthPose& model) const;
  bool FitDepthInBound(const std::vector<int>& indices, AffineDepthPose* model) const;
  bool PlanarTwin(const AffineDepthPose& best, AffineDepthPose* twin);

  const RelposeProblem& p_;
  const HybridEstimatorOptions& o_;
  MsacWeights w_;  // the Sampson weight changes once at low parallax (LowerSampsonWeightAtLowParallax)
  MinimalSolvers solvers_;
  IndexSampler sampler_;
  InlierSets inliers_;
  InlierSets lo_inliers_, lo_subset_;
  double median_prior0_ = 1.0, median_prior1_ = 1.0;  // of the valid priors (the shift bounds' reference)
  std::vector<int> pool_;
  int num_lo_ = 0;
  // Guided sampling (RelposeProblem::guided): which correspondences are guided, and those of them with both priors.
  std::vector<char> guided_mask_;
  std::vector<int> guided_depth_;
};

RelposeRefinerOptions Engine::RefinerOptions(int max_iterations) const {
  RelposeRefinerOptions ro;
  ro.max_iterations = max_iterations;
  ro.sampson_weight = w_.sampson_weight;
  ro.refine_shift = w_.use_shift;
  ro.max_shift = o_.max_shift_ratio;
  ro.shift_reference0 = median_prior0_;
  ro.shift_reference1 = median_prior1_;
  ro.function_tolerance = kRefinementFunctionTolerance;
  return ro;
}

bool Engine::Refine(AffineDepthPose* model, const InlierSets& in, int max_iterations) {
  return RefineRelpose(p_, in.reproj0, in.reproj1, in.sampson, RefinerOptions(max_iterations), model);
}

// Whether |shift0| and |shift1| are within max_shift_ratio times the views' median priors (always true when the
// bound is 0). The refiner keeps its steps within the bound; every other source of depth parameters (minimal
// solvers, the depth fits of point models and of the Sampson-only output) is checked with this, so that no model
// out of the bound is scored, optimised or returned.
bool Engine::ShiftsInBound(const AffineDepthPose& m) const {
  return !(o_.max_shift_ratio > 0.0) || (std::abs(m.shift0) <= o_.max_shift_ratio * median_prior0_ &&
                                         std::abs(m.shift1) <= o_.max_shift_ratio * median_prior1_);
}

// FitDepthParameters on `indices` for the model's pose, within the shift bound: the affine fit when its shifts are in
// bound, the scale-only fit (shifts 0) otherwise. The model is unchanged when neither fit is determined.
bool Engine::FitDepthInBound(const std::vector<int>& indices, AffineDepthPose* model) const {
  AffineDepthPose fit = *model;
  if (FitDepthParameters(p_, indices, w_.use_shift, &fit) && ShiftsInBound(fit)) {
    *model = fit;
    return true;
  }
  if (!w_.use_shift) return false;
  fit = *model;
  if (!FitDepthParameters(p_, indices, false, &fit)) return false;
  *model = fit;
  return true;
}

// The depth corrections of the final pose: scale, shifts and |t| by least squares of the reprojection errors
// of the depth inliers with R and the direction of t fixed (rounds of fit and inlier re-selection), kept when
// the MSAC score does not get worse. Their standard deviations say whether the priors determine them at all
// (tiny baselines, pure rotation: they do not).
void Engine::FitDepthCorrections(AffineDepthPose* model, double* score, HybridEstimate* result) {
  RelposeRefinerOptions ro = RefinerOptions(o_.final_max_lm_iterations);
  ro.refine_pose = false;
  ro.refine_focal = false;
  const std::vector<int> none;
  // (a) Least squares of the depth inliers' reprojection errors from the current depth parameters; its
  // covariance says whether the priors determine the corrections at all.
  AffineDepthPose m = *model;
  double s = *score;
  InlierSets in = inliers_;
  for (int round = 0; round < 3; ++round) {
    if (in.reproj0.empty() && in.reproj1.empty()) break;
    AffineDepthPose refined = m;
    RelposeRefinerSummary sum;
    if (!RefineRelpose(p_, in.reproj0, in.reproj1, none, ro, &refined, &sum)) break;
    const double sr = ScoreModel(p_, refined, w_);
    if (!(sr <= s)) break;
    m = refined, s = sr;
    result->sigma_shift0 = sum.sigma_shift0 / median_prior0_;
    result->sigma_shift1 = sum.sigma_shift1 / median_prior1_;
    result->sigma_scale = sum.sigma_scale / m.scale;
    InlierSets check;
    ComputeInliers(p_, m, w_, &check);
    const bool same = check.reproj0 == in.reproj0 && check.reproj1 == in.reproj1;
    in = check;
    if (same) break;
  }
  *model = m;
  *score = s;
  inliers_ = in;
  if (!o_.depth_fit_regression || (result->low_parallax_weighting && !o_.low_parallax_depth_fit_regression)) return;
  // (b) The triangulated epipolar inliers regressed on their priors with weights that treat well-triangulated
  // points alike: pixel residuals weigh near points far more than far ones, so (a) fits the near surfaces and
  // lets the relative error of the far ones grow wherever the priors are not exactly affine. Taken when it keeps
  // at least 90% of (a)'s depth inliers and its shifts are within the bound.
  AffineDepthPose r = *model;
  const double angular_noise = 1.0 / (p_.pixel_scale0 * r.f0);
  // Beyond the shift bound, the best line on the bound's edge (depth_fit_regression_in_bound) rather than none.
  const bool in_bound = o_.depth_fit_regression_in_bound && o_.max_shift_ratio > 0.0;
  const double bound0 = in_bound ? o_.max_shift_ratio * median_prior0_ * (1.0 - 1e-9) : 0.0;
  const double bound1 = in_bound ? o_.max_shift_ratio * median_prior1_ * (1.0 - 1e-9) : 0.0;
  if (!FitDepthParametersWeighted(p_, inliers_.sampson, w_.use_shift, angular_noise, &r, bound0, bound1)) return;
  if (o_.max_shift_ratio > 0.0 && (std::abs(r.shift0) > o_.max_shift_ratio * median_prior0_ ||
                                   std::abs(r.shift1) > o_.max_shift_ratio * median_prior1_)) {
    return;
  }
  InlierSets rin;
  ComputeInliers(p_, r, w_, &rin);
  const size_t depth_a = inliers_.reproj0.size() + inliers_.reproj1.size();
  if (rin.reproj0.size() + rin.reproj1.size() < 0.9 * depth_a) return;
  *model = r;
  *score = ScoreModel(p_, r, w_);
  inliers_ = rin;
}

// Focal modes (focal_depth_from_joint): the depth corrections of the joint estimate `joint` (with its inliers and
// score), FitDepthCorrections on it, carried over to the final model: its rotation, direction of t and focal lengths
// stay (the same focal lengths as the joint estimate's), and scale, shifts and |t| come from the joint estimate's fit.
// The last refinement moved the pose with the focal lengths held, and depths triangulated with a pose and focal
// lengths that were not estimated together are distorted, the far ones most. The final model's epipolar inliers are
// unchanged and its depth inliers recomputed; its score stays that of the corrections fitted to it (Run).
void Engine::DepthCorrectionsOfJointEstimate(AffineDepthPose joint, const InlierSets& joint_inliers, double joint_score,
                                             AffineDepthPose* model, HybridEstimate* result) {
  // Standard deviations as FitDepthCorrections gives them, from its least squares of the reprojection errors; where
  // those do not improve the joint estimate's score, at the joint estimate itself.
  RelposeRefinerOptions ro = RefinerOptions(0);
  ro.refine_pose = false;
  ro.refine_focal = false;
  RelposeRefinerSummary sum;
  const std::vector<int> none;
  AffineDepthPose at = joint;
  HybridEstimate fit;
  if (RefineRelpose(p_, joint_inliers.reproj0, joint_inliers.reproj1, none, ro, &at, &sum)) {
    fit.sigma_shift0 = sum.sigma_shift0 / median_prior0_;
    fit.sigma_shift1 = sum.sigma_shift1 / median_prior1_;
    fit.sigma_scale = sum.sigma_scale / at.scale;
  }
  fit.low_parallax_weighting = result->low_parallax_weighting;
  inliers_ = joint_inliers;
  FitDepthCorrections(&joint, &joint_score, &fit);
  result->sigma_shift0 = fit.sigma_shift0;
  result->sigma_shift1 = fit.sigma_shift1;
  result->sigma_scale = fit.sigma_scale;
  AffineDepthPose m = *model;
  m.scale = joint.scale;
  m.shift0 = joint.shift0;
  m.shift1 = joint.shift1;
  m.t = model->t.normalized() * joint.t.norm();
  ComputeInliers(p_, m, w_, &inliers_);
  *model = m;
}

// The last refinement with down-weighted reprojection terms (options.final_reprojection_weight, or
// low_parallax_final_reprojection_weight after the low-parallax switch): the
// depth priors have picked the hypothesis, the inliers and the focal lengths; the epipolar evidence of
// accurate matches then sets the pose, which monocular depth biases when it is distorted. Rounds of
// (refine, re-select inliers); a round is kept only if it keeps >= 95% of the epipolar inliers.
// Levenberg-Marquardt starts at the joint estimate, so directions the epipolar cost leaves flat
// (small baselines) stay close to it. The focal lengths are refined only with depth terms and refine_focal (the
// epipolar-only refinement keeps those the search and TakeEpipolarFocal gave).
void Engine::LeanOnEpipolarEvidence(double reprojection_weight, bool refine_focal, AffineDepthPose* model,
                                    double* score) {
  if (o_.epipolar_focal_max_sigma > 0.0 && p_.mode != CameraMode::kCalibrated) TakeEpipolarFocal(model, score);
  const bool epipolar_only = reprojection_weight == 0.0;
  RelposeRefinerOptions ro = RefinerOptions(o_.final_max_lm_iterations);  // with the shift bound
  ro.reprojection_weight = reprojection_weight;
  ro.refine_focal = refine_focal && !epipolar_only;
  ro.cauchy_scale = FinalCauchyScale(*model);
  const std::vector<int> none;
  for (int round = 0; round < 3; ++round) {
    AffineDepthPose refined = *model;
    if (!RefineRelpose(p_, epipolar_only ? none : inliers_.reproj0, epipolar_only ? none : inliers_.reproj1,
                       inliers_.sampson, ro, &refined)) {
      return;
    }
    if (epipolar_only) FitDepthInBound(inliers_.sampson, &refined);
    const std::vector<int> before = inliers_.sampson;
    if (!KeepIfEpipolarInliersRemain(refined, model, score) || inliers_.sampson == before) break;
  }
  // With depth terms, scale and shifts come out of the joint refinement, where a small baseline leaves them weakly
  // tied to the pose: they drift along flat directions of the cost, and FitDepthCorrections then starts from the
  // drift. The fit of the priors to the epipolar inliers' triangulated depths, as after an epipolar-only refinement,
  // is the better start (held-out low parallax calibrated: depth corrections within 1.25x of the oracle's error
  // 40.6% -> 45.7%; docs/benchmarks.md section 11, update of 2026-12-07 (later)). Taken whatever its MSAC score,
  // which always prefers the joint refinement's values.
  if (!epipolar_only && o_.mixed_refinement_depth_from_triangulation) {
    AffineDepthPose fit = *model;
    if (FitDepthInBound(inliers_.sampson, &fit)) {
      *model = fit;
      ComputeInliers(p_, fit, w_, &inliers_);
      *score = ScoreModel(p_, fit, w_);
    }
  }
}

// The Cauchy scale of the last refinement: final_cauchy_ratio times the epipolar inliers' robust noise level
// (1.4826 x their median absolute Sampson residual, pixels), so that it adapts to the matches: accurate matches with a
// few mislocalised ones near the threshold get a small scale, uniformly noisy ones a scale near the threshold (close
// to least squares). 0 when the option is 0.
double Engine::FinalCauchyScale(const AffineDepthPose& model) const {
  if (!(o_.final_cauchy_ratio > 0.0) || inliers_.sampson.empty()) return 0.0;
  return o_.final_cauchy_ratio * SampsonNoiseLevel(model, w_.sampson_weight);
}

// The epipolar inliers' robust noise level: 1.4826 x their median absolute Sampson residual (pixels, times
// sqrt(sampson_weight)); the inlier set must not be empty.
double Engine::SampsonNoiseLevel(const AffineDepthPose& model, double sampson_weight) const {
  std::vector<double> res;
  EvaluateRelposeResiduals(p_, {}, {}, inliers_.sampson, sampson_weight, model, &res);
  for (double& r : res) r = std::abs(r);
  return 1.4826 * UpperMedian(std::move(res));
}

// The point method's last refinement under that loss: pose (and focal lengths) on the epipolar inliers, rounds of
// (refine, re-select inliers), each kept when >= 95% of the epipolar inliers remain.
void Engine::RobustPointRefinement(AffineDepthPose* model, double* score) {
  RelposeRefinerOptions ro = RefinerOptions(o_.final_max_lm_iterations);
  ro.reprojection_weight = 0.0;
  ro.refine_focal = true;
  ro.cauchy_scale = FinalCauchyScale(*model);
  if (!(ro.cauchy_scale > 0.0)) return;
  const std::vector<int> none;
  for (int round = 0; round < 3; ++round) {
    AffineDepthPose refined = *model;
    if (!RefineRelpose(p_, none, none, inliers_.sampson, ro, &refined)) return;
    const std::vector<int> before = inliers_.sampson;
    if (!KeepIfEpipolarInliersRemain(refined, model, score) || inliers_.sampson == before) return;
  }
}

// Takes `refined` (model, score and inliers) when it keeps >= 95% of the current epipolar inliers and at least
// min_depth_share of each view's depth (reprojection) inliers.
bool Engine::KeepIfEpipolarInliersRemain(const AffineDepthPose& refined, AffineDepthPose* model, double* score,
                                         double min_depth_share) {
  InlierSets check;
  ComputeInliers(p_, refined, w_, &check);
  if (check.sampson.size() < 0.95 * inliers_.sampson.size()) return false;
  if (check.reproj0.size() < min_depth_share * inliers_.reproj0.size() ||
      check.reproj1.size() < min_depth_share * inliers_.reproj1.size()) {
    return false;
  }
  *model = refined;
  *score = ScoreModel(p_, refined, w_);
  inliers_ = std::move(check);
  return true;
}

// Focal modes: the focal lengths of the epipolar geometry alone, where it determines them. The joint estimate takes
// its focal lengths from the depth priors as much as from the matches, and a smooth distortion of the priors (a
// few percent) shifts them by about as much, whereas accurate matches over a well-spread baseline pin them to a
// fraction of a percent. So the pose and focal lengths are refined on the Sampson inliers alone, starting at the
// joint estimate, under the last refinement's Cauchy loss (a tail of mislocalised matches inside the threshold
// biases least-squares focal lengths as it biases the pose), and taken when the Gauss-Newton standard deviation of
// every focal length is at most epipolar_focal_max_sigma (relative), a focal length moved by more than 3 of them,
// and >= 95% of the epipolar inliers remain (shared focal: also a deviation up to epipolar_focal_wide_sigma and a
// move of more than 5 of them, as in forward motion, where the priors' distortion sets the joint focal); elsewhere
// (small baselines, noisy matches: a flat epipolar cost; or a joint estimate the epipolar evidence does not reject)
// the depth priors keep setting them.
void Engine::TakeEpipolarFocal(AffineDepthPose* model, double* score) {
  RelposeRefinerOptions ro = RefinerOptions(o_.final_max_lm_iterations);
  ro.reprojection_weight = 0.0;
  ro.refine_focal = true;
  ro.cauchy_scale = FinalCauchyScale(*model);
  const std::vector<int> none;
  AffineDepthPose refined = *model;
  RelposeRefinerSummary sum;
  if (!RefineRelpose(p_, none, none, inliers_.sampson, ro, &refined, &sum)) return;
  const bool two = p_.mode == CameraMode::kTwoFocal;
  const double rel0 = sum.sigma_f0 / refined.f0, rel1 = two ? sum.sigma_f1 / refined.f1 : 0.0;
  // A shared focal length the epipolar evidence determines less precisely (epipolar_focal_wide_sigma) must be
  // rejected by more of its deviations.
  const bool precise = rel0 <= o_.epipolar_focal_max_sigma && rel1 <= o_.epipolar_focal_max_sigma;
  const bool wide = !precise && p_.mode == CameraMode::kSharedFocal && rel0 <= o_.epipolar_focal_wide_sigma;
  if (!precise && !wide) return;
  const double k = precise ? 3.0 : 5.0;
  // Only where the epipolar evidence rejects the joint focal lengths (k sigma): within its noise the joint estimate
  // is as good, and the Sampson-only pose can slide along a valley its focal-length deviation does not show.
  const bool rejects = std::abs(refined.f0 - model->f0) > k * sum.sigma_f0 ||
                       (two && std::abs(refined.f1 - model->f1) > k * sum.sigma_f1);
  if (!rejects) return;
  FitDepthInBound(inliers_.sampson, &refined);
  // Two focal lengths: where the optical axes (nearly) meet, F does not fix them at all (Bougnoux's formula is
  // singular there), and the Sampson-only refinement can slide far along a flat valley whose end still looks precise
  // (a rendered arc pair with 0.5 px keypoints: 508 / 323 px -> 1859 / 1164 px, 0.5% deviation, pose 0.1 -> 45 deg).
  // Then the depth priors are the evidence, and a move that costs a view more than half of its depth inliers (912 ->
  // 57 there) is one they reject outright. A shared focal length is fixed by F in that configuration; there the
  // same rule refused moves that corrected joint focal lengths 3.3-7.4x off (docs/benchmarks.md section 11, updates of
  // 2026-12-07 (morning)), so it is two focal only.
  KeepIfEpipolarInliersRemain(refined, model, score, two ? kTwoFocalEpipolarMinDepthShare : 0.0);
}

// Focal modes: the standard deviations of the focal lengths at the final model under the cost of its data types
// (reprojection and Sampson inliers), pose, scale and shifts free, i.e. the marginal ones. Where a small baseline with
// little rotation lets focal length, shifts and translation trade off along a flat valley, they are large however
// well the model fits: the focal of such a pair is not evidence (focal_estimator weighs it accordingly).
void Engine::FocalSigmas(const AffineDepthPose& model, HybridEstimate* result) const {
  RelposeRefinerOptions ro = RefinerOptions(0);
  ro.refine_focal = true;
  ro.refine_depth = w_.use_reprojection;
  const std::vector<int> none;
  AffineDepthPose m = model;
  RelposeRefinerSummary sum;
  if (!RefineRelpose(p_, w_.use_reprojection ? inliers_.reproj0 : none, w_.use_reprojection ? inliers_.reproj1 : none,
                     w_.use_sampson ? inliers_.sampson : none, ro, &m, &sum)) {
    return;
  }
  result->sigma_focal0 = sum.sigma_f0 / m.f0;
  result->sigma_focal1 = p_.mode == CameraMode::kTwoFocal ? sum.sigma_f1 / m.f1 : result->sigma_focal0;
}

// Whether the epipolar inliers show parallax at all: false when a rotation alone (the least-squares rotation between
// their rays, with the model's focal lengths) transfers x0 to within a median distance of x1 (pixels, view 1) of 3
// times the inliers' robust noise level (1.4826 x their median Sampson error). Without parallax the depth corrections
// are not determined by the matches, only by the priors' own errors: a translation fitted to a smooth distortion of
// the priors makes a scale-only fit look precise (the covariance cannot see that bias: 15 of 30 pure-rotation pairs
// in depth_observable_test), so the flag must not rest on the standard deviations alone. true when there are too
// few epipolar inliers to judge by.
double Engine::ParallaxPixels(const AffineDepthPose& model) const {
  constexpr double kNotTheQuestion = std::numeric_limits<double>::infinity();
  const std::vector<int>& in = inliers_.sampson;
  if (in.size() < 5) return kNotTheQuestion;
  std::vector<Eigen::Vector3d> y0(in.size()), y1(in.size());
  for (size_t k = 0; k < in.size(); ++k) {
    y0[k] = Eigen::Vector3d(p_.x0[in[k]].x() / model.f0, p_.x0[in[k]].y() / model.f0, 1.0);
    y1[k] = Eigen::Vector3d(p_.x1[in[k]].x() / model.f1, p_.x1[in[k]].y() / model.f1, 1.0);
  }
  // argmax trace(R^T sum r1 r0^T) over rotations (Kabsch) on the unit rays of the points with use[k].
  auto fit_rotation = [&](const std::vector<char>& use) {
    Eigen::Matrix3d cross = Eigen::Matrix3d::Zero();
    for (size_t k = 0; k < in.size(); ++k) {
      if (use[k]) cross.noalias() += y1[k].normalized() * y0[k].normalized().transpose();
    }
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(cross, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
    d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
    return Eigen::Matrix3d(svd.matrixU() * d * svd.matrixV().transpose());
  };
  // Transfer distances (pixels, view 1); false when a point is rotated by 90 deg or more.
  auto transfers = [&](const Eigen::Matrix3d& R, std::vector<double>* out) {
    out->resize(in.size());
    for (size_t k = 0; k < in.size(); ++k) {
      const Eigen::Vector3d r = R * y0[k];
      if (!(r.z() > 0.0)) return false;
      (*out)[k] = (p_.x1[in[k]] - model.f1 * r.head<2>() / r.z()).norm() * p_.pixel_scale1;
    }
    return true;
  };
  std::vector<char> use(in.size(), 1);
  std::vector<double> transfer;
  Eigen::Matrix3d R = fit_rotation(use);
  if (!transfers(R, &transfer)) return kNotTheQuestion;
  // Once more without the matches the first rotation transfers worst (beyond twice the median): the epipolar inliers
  // of a model with an arbitrary epipole include a few mismatches that happen to lie near their epipolar lines, and
  // with hundreds of pixels of error each they pull a least-squares rotation by pixels (pure rotations then looked
  // like parallax: 34 of 530 scale-only pairs flagged observable, 1 after the refit; docs/benchmarks.md section 11,
  // update of 2026-12-06).
  const double cut = 2.0 * UpperMedian(transfer);
  for (size_t k = 0; k < in.size(); ++k) use[k] = transfer[k] <= cut;
  R = fit_rotation(use);
  if (!transfers(R, &transfer)) return kNotTheQuestion;
  return UpperMedian(std::move(transfer));
}

bool Engine::ParallaxMeasurable(const AffineDepthPose& model) const {
  return ParallaxPixels(model) > 3.0 * SampsonNoiseLevel(model, 1.0);
}

// HybridEstimatorOptions::low_parallax_sampson_factor: after the first local optimisation, where the best model's
// epipolar inliers, once the rotation that best transfers them is taken out, move by a median of less than
// low_parallax_noise_ratio times their noise level (SampsonNoiseLevel), the Sampson term's weight is lowered for the
// rest of the run. The direction of the translation is then uncertain to about noise / parallax in the epipolar
// error, and the depth priors determine it better. Hybrid score only (the Sampson-only score has nothing to
// balance). Returns whether it did.
bool Engine::LowerSampsonWeightAtLowParallax(const AffineDepthPose& best) {
  if (!(o_.low_parallax_sampson_factor < 1.0) || !w_.use_reprojection || !w_.use_sampson) return false;
  ComputeInliers(p_, best, w_, &inliers_);
  if (inliers_.sampson.size() < 5) return false;
  if (!(ParallaxPixels(best) < o_.low_parallax_noise_ratio * SampsonNoiseLevel(best, 1.0))) return false;
  w_.sampson_weight *= o_.low_parallax_sampson_factor;
  return true;
}

// Local optimisation in the manner of Lebeda et al. 2012 (LO+ with inner samples and a threshold schedule), as
// RansacLib and the paper's code run it: a least-squares fit on the inliers under a relaxed threshold, then
// num_lo_steps rounds of (least squares on a random subset of those inliers, then num_lsq_steps least-squares
// fits on random subsets of the inliers under a threshold shrinking from the relaxed one to the true one). Every
// fitted model is scored; the best of them and of the input is kept. The random subsets let the model leave the
// basin of its minimal sample (a plain LM from the current model does not).
void Engine::LocalOptimize(AffineDepthPose* model, double* score, bool from_point_solver) {
  ++num_lo_;
  AffineDepthPose m_init = *model;
  if (from_point_solver && w_.use_reprojection) {
    // A point-solver model's scale and shifts come from its 5-7 sample points only: refit them on all epipolar
    // inliers first.
    ComputeInliers(p_, m_init, w_, &lo_inliers_);
    AffineDepthPose refit = m_init;
    if (!lo_inliers_.sampson.empty() && FitDepthInBound(lo_inliers_.sampson, &refit)) {
      const double s = ScoreModel(p_, refit, w_);
      if (s < ScoreModel(p_, m_init, w_)) m_init = refit;
    }
  }
  auto consider = [&](const AffineDepthPose& m) {
    if (!ShiftsInBound(m)) return;
    const double s = ScoreModel(p_, m, w_, *score);
    // Ties are accepted: once the inlier errors are below the rounding of the truncated outlier terms the score
    // stops changing, but the least-squares model is the better one.
    if (s <= *score) {
      *score = s;
      *model = m;
    }
  };
  const int lo_lm_iterations =
      p_.mode == CameraMode::kTwoFocal ? o_.lo_max_lm_iterations_two_focal : o_.lo_max_lm_iterations;
  const double mult = o_.lo_threshold_multiplier;
  const MsacWeights relaxed = w_.Relaxed(mult);
  // consider(m), then m's inliers under `wi` into *in: one pass over the correspondences when m is scored.
  auto consider_then_select = [&](const AffineDepthPose& m, const MsacWeights& wi, InlierSets* in) {
    if (!ShiftsInBound(m)) {
      ComputeInliers(p_, m, wi, in);
      return;
    }
    const double s = ScoreModelAndComputeInliers(p_, m, w_, wi, in);
    if (s <= *score) {
      *score = s;
      *model = m;
    }
  };
  // 1. Least squares on the inliers under the relaxed threshold (at most lo_first_fit_sample_size of their residual
  // terms, drawn at random).
  ComputeInliers(p_, m_init, relaxed, &lo_inliers_);
  bool refined;
  if (o_.lo_first_fit_sample_size > 0 && lo_inliers_.Total() > o_.lo_first_fit_sample_size) {
    DrawSubset(lo_inliers_, o_.lo_first_fit_sample_size, &lo_subset_);
    refined = Refine(&m_init, lo_subset_, lo_lm_iterations);
  } else {
    refined = Refine(&m_init, lo_inliers_, lo_lm_iterations);
  }
  if (o_.num_lo_steps <= 0) {
    if (refined) consider(m_init);
    return;
  }
  // 2. Inner rounds on subsets of the inliers of m_init.
  InlierSets base;
  if (refined) {
    consider_then_select(m_init, w_, &base);
  } else {
    ComputeInliers(p_, m_init, w_, &base);
  }
  const int num_base = base.Total();
  if (num_base == 0) return;
  const int k_min = std::max(MinimalSampleSize(p_.mode, MinimalSolverKind::kDepth, o_.estimate_shift),
                             MinimalSampleSize(p_.mode, MinimalSolverKind::kPoint, o_.estimate_shift));
  const int inner_size = std::max(std::min(o_.lo_inner_sample_multiplier * k_min, num_base / 2), 2 * k_min);
  const int lsq_size = o_.lo_lsq_sample_size;
  const int num_lsq = std::max(1, o_.num_lo_lsq_steps);
  for (int r = 0; r < o_.num_lo_steps; ++r) {
    AffineDepthPose m = m_init;
    DrawSubset(base, inner_size, &lo_subset_);
    if (!Refine(&m, lo_subset_, lo_lm_iterations)) continue;
    // Each fitted model is scored (consider) in the same pass that selects its inliers for the next fit.
    bool last_fit_ok = true;
    for (int i = 0; i < num_lsq; ++i) {
      const double f = num_lsq > 1 ? static_cast<double>(i) / (num_lsq - 1) : 1.0;
      const MsacWeights wi = w_.Relaxed(mult + (1.0 - mult) * f);  // mult -> 1
      consider_then_select(m, wi, &lo_inliers_);
      DrawSubset(lo_inliers_, lsq_size, &lo_subset_);
      if (!Refine(&m, lo_subset_, lo_lm_iterations)) {  // m unchanged, and already considered
        last_fit_ok = false;
        break;
      }
    }
    if (last_fit_ok) consider(m);
  }
}

// A random subset of k of the pooled inliers of all data types (all of them when there are at most k).
void Engine::DrawSubset(const InlierSets& in, int k, InlierSets* out) {
  const int n0 = static_cast<int>(in.reproj0.size()), n1 = static_cast<int>(in.reproj1.size());
  const int n = in.Total();
  out->reproj0.clear();
  out->reproj1.clear();
  out->sampson.clear();
  auto push = [&](int j) {
    if (j < n0) out->reproj0.push_back(in.reproj0[j]);
    else if (j < n0 + n1) out->reproj1.push_back(in.reproj1[j - n0]);
    else out->sampson.push_back(in.sampson[j - n0 - n1]);
  };
  if (n <= k) {
    *out = in;
    return;
  }
  pool_.resize(n);
  for (int j = 0; j < n; ++j) pool_[j] = j;
  for (int j = 0; j < k; ++j) {  // partial Fisher-Yates
    const int l = j + static_cast<int>(sampler_.Uniform() * (n - j));
    std::swap(pool_[j], pool_[std::min(l, n - 1)]);
    push(pool_[j]);
  }
}

// The planar twin of `best` (planar_twin_min_support), for the Sampson-only score: a homography fitted to its
// epipolar inliers by linear least squares with two rounds of re-selection (transfer error within 2x the epipolar
// threshold), and if it holds enough of them and the baseline is at least kMinPlanarTwinBaseline of the plane's
// distance, the decomposition of it that is further from `best`, with |t| and the focal lengths of `best` (the depth
// parameters do not enter this score; the output's are fitted at the end). False when there is no such twin.
bool Engine::PlanarTwin(const AffineDepthPose& best, AffineDepthPose* twin) {
  if (w_.use_reprojection || !w_.use_sampson) return false;
  ComputeInliers(p_, best, w_, &inliers_);
  const std::vector<int>& in = inliers_.sampson;
  const int n = static_cast<int>(in.size());
  if (n < 8 || !(best.t.norm() > 0.0)) return false;
  std::vector<Eigen::Vector2d> y0(n), y1(n);  // normalised coordinates
  for (int k = 0; k < n; ++k) {
    y0[k] = p_.x0[in[k]] / best.f0;
    y1[k] = p_.x1[in[k]] / best.f1;
  }
  const double threshold = 2.0 * o_.epipolar_threshold / (p_.pixel_scale1 * best.f1);
  std::vector<int> support(n);
  for (int k = 0; k < n; ++k) support[k] = k;
  Eigen::Matrix3d H;
  for (int round = 0; round < 3; ++round) {
    if (!FitHomographyLinear(y0, y1, support, &H)) return false;
    std::vector<int> next;
    for (int k = 0; k < n; ++k) {
      if (HomographyTransferError(H, y0[k], y1[k]) < threshold) next.push_back(k);
    }
    if (next.size() < 8) return false;
    support.swap(next);
  }
  if (support.size() < o_.planar_twin_min_support * n) return false;
  const std::vector<PlanarPose> poses = DecomposeHomography(H, y0, y1, support);
  if (poses.size() != 2) return false;
  // The decomposition closer to `best` is its own; the other one is the twin.
  auto distance = [&](const PlanarPose& q) {
    const PoseCosines c = CosinesBetween(q.R, q.t, best.R, best.t);
    return std::acos(c.rotation) + std::acos(c.translation);
  };
  const PlanarPose& q = distance(poses[0]) > distance(poses[1]) ? poses[0] : poses[1];
  if (!(q.t.norm() >= kMinPlanarTwinBaseline)) return false;
  *twin = best;
  twin->R = q.R;
  twin->t = q.t.normalized() * best.t.norm();
  return DistinctModels(best, *twin);
}

HybridEstimate Engine::Run() {
  const auto start = std::chrono::steady_clock::now();
  HybridEstimate result;
  const CameraMode mode = p_.mode;
  const int k_depth = MinimalSampleSize(mode, MinimalSolverKind::kDepth, o_.estimate_shift);
  const int k_point = MinimalSampleSize(mode, MinimalSolverKind::kPoint, o_.estimate_shift);
  const bool depth_ok = o_.solvers != SolverChoice::kPointsOnly &&
                        static_cast<int>(p_.with_both_depths.size()) >= k_depth;
  const bool point_ok = o_.solvers != SolverChoice::kDepthOnly && p_.size() >= k_point;
  if (!depth_ok && !point_ok) return result;

  std::vector<int> all(p_.size());
  for (int i = 0; i < p_.size(); ++i) all[i] = i;

  AffineDepthPose best;
  double best_score = std::numeric_limits<double>::infinity();
  bool have_best = false;
  InlierRatios ratios;
  int required = o_.max_iterations;
  std::vector<AffineDepthPose> models;
  models.reserve(16);
  int sample[8];
  std::vector<int> sample_indices;

  // As in RansacLib: a minimal model that beats the best MINIMAL model so far is locally optimised, and the result
  // competes with the best optimised model. (Comparing new minimal models with the optimised score instead would
  // almost never optimise a model from another basin.) No local optimisation in the first lo_starting_iterations.
  // As in PoseLib, a minimal model is also a candidate when it has more inliers than any minimal model before
  // (even with a worse score): far-point scenes have two basins of nearly equal score, and a model of the right one
  // may count more inliers while its noisy minimal fit scores worse.
  double best_min_score = std::numeric_limits<double>::infinity();
  int best_min_count = 0;
  AffineDepthPose best_min;
  double best_min_model_score = std::numeric_limits<double>::infinity();  // score of best_min itself
  bool best_min_from_points = false;
  bool lo_started = false;
  // The best score of a minimal model of another basin that was optimised (see alt_basin_lo_margin).
  double alt_min_score = std::numeric_limits<double>::infinity();
  // Guided sampling (RelposeProblem::guided): a fraction g of the draws comes from the guided correspondences, each
  // kind of draw picks its solver by its own inlier ratios, and the stopping criterion counts all four
  // (pool, solver) combinations with their probabilities.
  const bool guided_depth_ok = depth_ok && static_cast<int>(guided_depth_.size()) >= k_depth;
  const bool guided_point_ok =
      point_ok && !guided_mask_.empty() && static_cast<int>(p_.guided.size()) >= k_point;
  const bool guided = guided_depth_ok || guided_point_ok;
  const double g = guided ? o_.guided_sampling_fraction : 0.0;
  InlierRatios guided_ratios;
  auto depth_solver_probability = [](double P_d, double P_p, bool d_ok, bool p_ok) {
    return d_ok ? (p_ok ? FirstSolverProbability(P_d, P_p) : 1.0) : 0.0;
  };
  auto update_termination = [&]() {
    ComputeInliers(p_, best, w_, &inliers_);
    ratios = ComputeRatios(p_, inliers_, w_);
    const double P_d = AllInlierProbability(ratios.both_depths, k_depth);
    const double P_p = AllInlierProbability(ratios.sampson, k_point);
    const double qd = depth_solver_probability(P_d, P_p, depth_ok, point_ok);
    if (!guided) {
      required = RequiredIterations({qd, 1.0 - qd}, {P_d, P_p}, o_.confidence, o_.max_iterations);
      return;
    }
    guided_ratios = ComputeGuidedRatios(inliers_, w_, guided_mask_, static_cast<int>(p_.guided.size()),
                                        static_cast<int>(guided_depth_.size()));
    const double gP_d = AllInlierProbability(guided_ratios.both_depths, k_depth);
    const double gP_p = AllInlierProbability(guided_ratios.sampson, k_point);
    const double gqd = depth_solver_probability(gP_d, gP_p, guided_depth_ok, guided_point_ok);
    required = RequiredIterations({(1.0 - g) * qd, (1.0 - g) * (1.0 - qd), g * gqd, g * (1.0 - gqd)},
                                  {P_d, P_p, gP_d, gP_p}, o_.confidence, o_.max_iterations);
  };
  // The best model of another basin (rotation or translation direction apart, see DistinctModels): two basins can
  // score within rounding of each other after local optimisation (far-point scenes with a bas-relief-like
  // ambiguity), and only the final refinement decides between them; see the end of Run().
  AffineDepthPose runner_up;
  double runner_up_score = std::numeric_limits<double>::infinity();
  auto compete = [&](const AffineDepthPose& m, double score) {
    if (score < best_score) {
      if (have_best && DistinctModels(best, m)) {
        runner_up = best;
        runner_up_score = best_score;
      }
      best_score = score;
      best = m;
      have_best = true;
    } else if (score < runner_up_score && DistinctModels(best, m)) {
      runner_up = m;
      runner_up_score = score;
    }
  };
  auto optimize_and_compete = [&](AffineDepthPose m, double score, bool from_points) {
    LocalOptimize(&m, &score, from_points);
    compete(m, score);
  };
  // The alternative-basin candidate found before the first local optimisation: optimised with it, if it is still
  // of another basin than the best and within the margin of the best minimal score.
  AffineDepthPose pending_alt;
  double pending_alt_score = std::numeric_limits<double>::infinity();
  bool pending_alt_from_points = false;
  auto optimize_pending_alt = [&]() {
    if (pending_alt_score <= (1.0 + o_.alt_basin_lo_margin) * best_min_score && DistinctModels(best, pending_alt)) {
      optimize_and_compete(pending_alt, pending_alt_score, pending_alt_from_points);
    }
    pending_alt_score = std::numeric_limits<double>::infinity();
  };
  // After the first local optimisation: the low-parallax weighting (its parallax measured on the optimised best), every
  // score kept so far under the new weights, and the best optimised once more under them.
  auto lower_at_low_parallax = [&]() {
    if (!LowerSampsonWeightAtLowParallax(best)) return;
    result.low_parallax_weighting = true;
    best_score = ScoreModel(p_, best, w_);
    if (std::isfinite(runner_up_score)) runner_up_score = ScoreModel(p_, runner_up, w_);
    best_min_model_score = ScoreModel(p_, best_min, w_);
    best_min_score = best_min_model_score;
    alt_min_score = std::numeric_limits<double>::infinity();
    optimize_and_compete(best, best_score, false);
  };
  // Point samples only in a focal mode: the extended minimum of that mode (see the options).
  const int points_only_minimum = mode == CameraMode::kTwoFocal     ? o_.min_iterations_two_focal_points
                                  : mode == CameraMode::kSharedFocal ? o_.min_iterations_shared_focal_points
                                                                     : 0;
  const int min_iterations =
      depth_ok ? o_.min_iterations : std::min(o_.max_iterations, std::max(o_.min_iterations, points_only_minimum));
  int it = 0;
  for (; it < o_.max_iterations; ++it) {
    if (it >= min_iterations && it >= required) break;
    if (!lo_started && it >= o_.lo_starting_iterations && have_best) {
      lo_started = true;
      optimize_and_compete(best_min, best_min_model_score, best_min_from_points);
      optimize_pending_alt();
      lower_at_low_parallax();
      update_termination();
    }
    const bool from_guide = guided && sampler_.Uniform() < g;
    const InlierRatios& r = from_guide ? guided_ratios : ratios;
    const double P_depth = AllInlierProbability(r.both_depths, k_depth);
    const double P_point = AllInlierProbability(r.sampson, k_point);
    const double q_depth = from_guide ? depth_solver_probability(P_depth, P_point, guided_depth_ok, guided_point_ok)
                                      : depth_solver_probability(P_depth, P_point, depth_ok, point_ok);
    const MinimalSolverKind kind =
        sampler_.Uniform() < q_depth ? MinimalSolverKind::kDepth : MinimalSolverKind::kPoint;
    if (kind == MinimalSolverKind::kDepth) {
      sampler_.Sample(from_guide ? guided_depth_ : p_.with_both_depths, k_depth, sample);
      ++result.num_depth_samples;
    } else {
      sampler_.Sample(from_guide ? p_.guided : all, k_point, sample);
      ++result.num_point_samples;
    }
    solvers_.Solve(kind, sample, &models);
    int local_best = -1;
    double local_score = 0.0;
    int local_alt = -1;
    double local_alt_score = 0.0;
    // Scored up to the bound of an alternative-basin candidate (below), which is never below best_min_score.
    const double alt_bound = std::min(alt_min_score, (1.0 + o_.alt_basin_lo_margin) * best_min_score);
    const double stop_above = o_.alt_basin_lo_margin > 0.0 ? alt_bound : best_min_score;
    for (int k = 0; k < static_cast<int>(models.size()); ++k) {
      if (!ShiftsInBound(models[k])) {
        // A depth-solver model out of the shift bound is not scored; a point model's depth parameters come from
        // its sample alone and are refitted without shifts (its pose stays a hypothesis either way).
        if (kind == MinimalSolverKind::kDepth) continue;
        sample_indices.assign(sample, sample + k_point);
        if (!FitDepthParameters(p_, sample_indices, false, &models[k])) models[k].shift0 = models[k].shift1 = 0.0;
      }
      int count = 0;
      const double sc = ScoreModelCounting(p_, models[k], w_, stop_above, best_min_count, &count);
      const bool better = sc < best_min_score, more = count > best_min_count;
      if (!better && !more) {
        if (stop_above > best_min_score && sc < alt_bound && (local_alt < 0 || sc < local_alt_score) &&
            DistinctModels(best, models[k])) {
          local_alt = k;
          local_alt_score = sc;
        }
        continue;
      }
      if (better) best_min_score = sc;
      if (more) best_min_count = count;
      local_best = k;
      local_score = sc;
    }
    if (local_best < 0 && local_alt >= 0) {
      // A minimal model of another basin than the best, within alt_basin_lo_margin of the best minimal score: its
      // basin may hold the better optimum (far points: minimal models of the right basin are noisy and can score
      // a few percent worse than a lucky one of the wrong basin, and would then never be optimised).
      // Before the first local optimisation it waits for it (see optimize_pending_alt).
      alt_min_score = local_alt_score;
      if (lo_started) {
        optimize_and_compete(models[local_alt], local_alt_score, kind == MinimalSolverKind::kPoint);
        update_termination();
      } else {
        pending_alt = models[local_alt];
        pending_alt_score = local_alt_score;
        pending_alt_from_points = kind == MinimalSolverKind::kPoint;
      }
      continue;
    }
    if (local_best < 0) continue;
    best_min = models[local_best];
    best_min_model_score = local_score;
    best_min_from_points = kind == MinimalSolverKind::kPoint;
    if (lo_started && o_.lo_skip_same_basin && best_min_model_score >= best_score && !DistinctModels(best, best_min)) {
      // The optimised best's basin, and no better than it: optimising it would end where the best is
      // (lo_skip_same_basin).
    } else if (lo_started) {
      optimize_and_compete(best_min, best_min_model_score, best_min_from_points);
    } else {
      compete(best_min, best_min_model_score);
    }
    update_termination();
  }
  if (!lo_started && have_best) {
    optimize_and_compete(best_min, best_min_model_score, best_min_from_points);
    optimize_pending_alt();
    lower_at_low_parallax();
  }
  result.iterations = it;

  if (have_best && o_.planar_twin_min_support > 0.0) {
    AffineDepthPose twin;
    if (PlanarTwin(best, &twin)) optimize_and_compete(twin, ScoreModel(p_, twin, w_), true);
  }

  if (have_best) {
    // Refine on the final inliers, re-select the inliers and refine once more; keep the result only if it improves
    // the MSAC score. The runner-up of another basin gets the same, and replaces the best if it then scores lower.
    auto final_refine = [&](AffineDepthPose* m, double* score) {
      ComputeInliers(p_, *m, w_, &inliers_);
      if (!o_.final_refinement) return;
      for (int round = 0; round < 2; ++round) {
        AffineDepthPose refined = *m;
        if (!Refine(&refined, inliers_, o_.final_max_lm_iterations)) break;
        const double s = ScoreModel(p_, refined, w_);
        if (!(s <= *score)) break;
        *m = refined;
        *score = s;
        ComputeInliers(p_, *m, w_, &inliers_);
      }
    };
    // Only a near tie (within 1% of the score) is worth the second refinement.
    if (o_.final_refinement && runner_up_score <= 1.01 * best_score) {
      final_refine(&runner_up, &runner_up_score);
      result.runner_up_score = runner_up_score;
    }
    final_refine(&best, &best_score);
    if (result.runner_up_score < best_score) {
      std::swap(best, runner_up);
      std::swap(best_score, runner_up_score);
      ComputeInliers(p_, best, w_, &inliers_);
      result.runner_up_won = true;
    }
    // At low parallax the epipolar error hardly constrains the translation's direction, so the last refinement keeps
    // more of the depth terms. In the focal modes the focal lengths then stay fixed: refined beside biased depth terms
    // they lost 1.6 AUC@10 on dev planar shared focal (docs/benchmarks.md section 11, updates of 2026-12-07).
    const bool low_parallax_mixed = result.low_parallax_weighting;
    const double final_reprojection_weight =
        low_parallax_mixed ? o_.low_parallax_final_reprojection_weight : o_.final_reprojection_weight;
    // The joint estimate, whose depth corrections the focal modes keep (focal_depth_from_joint). After the
    // low-parallax switch the mixed last refinement already takes them from the triangulation fit (madsfm-18).
    const bool depth_from_joint = o_.focal_depth_from_joint && p_.mode != CameraMode::kCalibrated &&
                                  !low_parallax_mixed && w_.use_reprojection && o_.final_depth_fit;
    const AffineDepthPose joint = best;
    const double joint_score = best_score;
    InlierSets joint_inliers;
    if (depth_from_joint) joint_inliers = inliers_;
    if (o_.final_refinement && final_reprojection_weight < 1.0 && w_.use_reprojection && w_.use_sampson &&
        !inliers_.sampson.empty()) {
      LeanOnEpipolarEvidence(final_reprojection_weight, !low_parallax_mixed, &best, &best_score);
    }
    if (o_.final_refinement && !w_.use_reprojection && w_.use_sampson && !inliers_.sampson.empty()) {
      RobustPointRefinement(&best, &best_score);
    }
    if (!w_.use_reprojection) {
      // Sampson-only scoring leaves scale and shifts as the sample gave them: fit them on all
      // epipolar inliers for the output.
      FitDepthInBound(inliers_.sampson, &best);
    } else if (o_.final_depth_fit) {
      FitDepthCorrections(&best, &best_score, &result);
      // best_score stays that of this fit: the comparisons with other searches (scale-only fallback, retry) are
      // between poses, each with the corrections that fit it best.
      if (depth_from_joint && best.f0 == joint.f0 && best.f1 == joint.f1) {
        DepthCorrectionsOfJointEstimate(joint, joint_inliers, joint_score, &best, &result);
      }
    }
    if (p_.mode != CameraMode::kCalibrated) FocalSigmas(best, &result);
    // Without shifts (scale-only model) their sigmas are NaN and only the scale's counts.
    const bool shifts_determined =
        !w_.use_shift || (result.sigma_shift0 <= o_.max_depth_sigma && result.sigma_shift1 <= o_.max_depth_sigma);
    // The scale-only model also needs parallax the matches show (ParallaxMeasurable); with shifts, a pure rotation
    // already leaves them undetermined (depth_observable_test: 0 of 30 such pairs flagged), and on the low-parallax
    // sets the check removed flagged runs of average quality (docs/benchmarks.md), so it is not applied there.
    result.depth_observable = w_.use_reprojection && shifts_determined && result.sigma_scale <= o_.max_depth_sigma &&
                              (w_.use_shift || ParallaxMeasurable(best));
    // A scale that ran off towards 0 or infinity carries no information: at a pure rotation every scale fits (the
    // second view's points far away transfer like a rotation), and the fits follow the flat cost outwards (4.7e10 on
    // one pair of depth_observable_test). Such a result gets the priors' own ratio of medians and says it is not
    // observable, instead of returning the drift.
    const double scale_reference = median_prior0_ / median_prior1_;
    if (!(best.scale >= scale_reference / kMaxScaleRatio && best.scale <= scale_reference * kMaxScaleRatio)) {
      best.scale = scale_reference;
      ComputeInliers(p_, best, w_, &inliers_);
      best_score = ScoreModel(p_, best, w_);
      result.depth_observable = false;
      result.sigma_scale = std::numeric_limits<double>::quiet_NaN();
      result.scale_reset = true;
    }
    result.model = best;
    // Under the options' weights, so that scores of searches with and without the low-parallax weighting compare.
    result.score = result.low_parallax_weighting ? ScoreModel(p_, best, MsacWeights::FromOptions(o_)) : best_score;
    const int n = p_.size();
    result.inliers_reproj0.assign(n, 0);
    result.inliers_reproj1.assign(n, 0);
    result.inliers_sampson.assign(n, 0);
    for (int i : inliers_.reproj0) result.inliers_reproj0[i] = 1;
    for (int i : inliers_.reproj1) result.inliers_reproj1[i] = 1;
    for (int i : inliers_.sampson) result.inliers_sampson[i] = 1;
    result.num_inliers_reproj0 = static_cast<int>(inliers_.reproj0.size());
    result.num_inliers_reproj1 = static_cast<int>(inliers_.reproj1.size());
    result.num_inliers_sampson = static_cast<int>(inliers_.sampson.size());
    const int support = w_.use_sampson ? result.num_inliers_sampson
                                       : std::max(result.num_inliers_reproj0, result.num_inliers_reproj1);
    result.success = support >= std::min(k_depth, k_point) && best.R.allFinite() && best.t.allFinite();
  }
  result.num_lo = num_lo_;
  result.runtime_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return result;
}

// Adds the search work of `other` (iterations, local optimisations, minimal samples) to `total`: a result that
// took several searches reports the work of all of them.
void AddSearchWork(const HybridEstimate& other, HybridEstimate* total) {
  total->iterations += other.iterations;
  total->num_lo += other.num_lo;
  total->num_depth_samples += other.num_depth_samples;
  total->num_point_samples += other.num_point_samples;
}

}  // namespace

HybridEstimate EstimateHybridRelpose(const RelposeProblem& problem, const HybridEstimatorOptions& options) {
  options.Check();
  for (size_t k = 0; k < problem.guided.size(); ++k) {
    if (problem.guided[k] < 0 || problem.guided[k] >= problem.size() ||
        (k > 0 && problem.guided[k] <= problem.guided[k - 1])) {
      throw std::invalid_argument("RelposeProblem::guided must hold sorted, distinct correspondence indices below " +
                                  std::to_string(problem.size()));
    }
  }
  const auto start = std::chrono::steady_clock::now();
  Engine engine(problem, options);
  HybridEstimate result = engine.Run();
  // A hybrid result that the depth priors do not support (depth inliers below 5% of its epipolar inliers) while
  // most matches have priors: on the held-out hard pairs every such run was a wrong basin (9.6-89 deg), reached
  // when a wrong best model stopped the depth sampling. One more search with another seed (derived from the
  // options' seed, so the result stays deterministic) replaces it when it scores lower. Pairs whose priors are
  // really useless pay one more search.
  const bool depth_less = options.retry_depth_less && options.solvers == SolverChoice::kHybrid &&
                          options.scoring == ScoringMode::kHybrid && result.success &&
                          2 * problem.with_both_depths.size() >= static_cast<size_t>(problem.size()) &&
                          result.num_inliers_reproj0 + result.num_inliers_reproj1 < 0.05 * result.num_inliers_sampson;
  if (depth_less) {
    HybridEstimatorOptions again = options;
    again.seed = options.seed ^ 0x9E3779B97F4A7C15ull;
    Engine second(problem, again);
    HybridEstimate retry = second.Run();
    if (retry.success && retry.score < result.score) std::swap(result, retry);
    AddSearchWork(retry, &result);  // `retry` now holds the search that was not kept
  }
  const bool check = options.epipolar_check_ratio > 0 && problem.mode == CameraMode::kCalibrated &&
                     options.solvers == SolverChoice::kHybrid && options.scoring == ScoringMode::kHybrid &&
                     result.success;
  if (check) {
    HybridEstimatorOptions po = options;
    po.solvers = SolverChoice::kPointsOnly;
    po.scoring = ScoringMode::kSampsonOnly;
    Engine points(problem, po);
    HybridEstimate competitor = points.Run();
    if (competitor.success &&
        competitor.num_inliers_sampson >= options.epipolar_check_ratio * result.num_inliers_sampson) {
      // Keep the point model's pose and focal lengths; its scale and shifts were fitted on its epipolar
      // inliers. Report the inliers of all three data types under the hybrid thresholds.
      const MsacWeights w = MsacWeights::FromOptions(options);
      InlierSets in;
      ComputeInliers(problem, competitor.model, w, &in);
      result.model = competitor.model;
      result.score = ScoreModel(problem, competitor.model, w);
      const int n = problem.size();
      result.inliers_reproj0.assign(n, 0);
      result.inliers_reproj1.assign(n, 0);
      result.inliers_sampson.assign(n, 0);
      for (int i : in.reproj0) result.inliers_reproj0[i] = 1;
      for (int i : in.reproj1) result.inliers_reproj1[i] = 1;
      for (int i : in.sampson) result.inliers_sampson[i] = 1;
      result.num_inliers_reproj0 = static_cast<int>(in.reproj0.size());
      result.num_inliers_reproj1 = static_cast<int>(in.reproj1.size());
      result.num_inliers_sampson = static_cast<int>(in.sampson.size());
      result.epipolar_check_switched = true;
    }
    AddSearchWork(competitor, &result);
  }
  const bool undetermined_shifts = options.scale_only_fallback && options.estimate_shift &&
                                   options.solvers == SolverChoice::kHybrid &&
                                   options.scoring == ScoringMode::kHybrid && result.success &&
                                   !result.depth_observable &&
                                   2 * problem.with_both_depths.size() >= static_cast<size_t>(problem.size());
  if (undetermined_shifts) {
    HybridEstimatorOptions scale_only = options;
    scale_only.estimate_shift = false;
    HybridEstimate fallback = EstimateHybridRelpose(problem, scale_only);
    // The simpler model replaces the result only when it explains the data at least as well (MSAC score): where
    // the priors really need shifts (affine monocular depth with a poorly determined focal length) it scores worse.
    if (fallback.success && fallback.score <= result.score) {
      std::swap(result, fallback);
      result.shifts_dropped = true;
      // The shifts were assumed 0, not measured: the corrections stay unobservable (seed_model must not build
      // low-parallax seeds from them).
      result.depth_observable = false;
    }
    AddSearchWork(fallback, &result);  // `fallback` now holds the search that was not kept
  }
  result.runtime_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace madsfm
