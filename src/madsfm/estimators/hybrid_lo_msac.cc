#include "madsfm/estimators/hybrid_lo_msac.h"

#include <chrono>
#include <cmath>
#include <limits>

#include "madsfm/estimators/hybrid_sampling.h"
#include "madsfm/estimators/minimal_solvers.h"
#include "madsfm/estimators/msac_scoring.h"
#include "madsfm/refinement/relpose_refiner.h"

namespace madsfm {
namespace {

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

class Engine {
 public:
  Engine(const RelposeProblem& p, const HybridEstimatorOptions& o)
      : p_(p), o_(o), w_(MsacWeights::FromOptions(o)), solvers_(p, o.estimate_shift), sampler_(o.seed) {}

  HybridEstimate Run();

 private:
  void LocalOptimize(AffineDepthPose* model, double* score, bool from_point_solver);
  bool Refine(AffineDepthPose* model, const InlierSets& inliers, int max_iterations);
  void LeanOnEpipolarEvidence(AffineDepthPose* model, double* score);

  const RelposeProblem& p_;
  const HybridEstimatorOptions& o_;
  const MsacWeights w_;
  MinimalSolvers solvers_;
  IndexSampler sampler_;
  InlierSets inliers_;
  int num_lo_ = 0;
};

bool Engine::Refine(AffineDepthPose* model, const InlierSets& in, int max_iterations) {
  RelposeRefinerOptions ro;
  ro.max_iterations = max_iterations;
  ro.sampson_weight = w_.sampson_weight;
  ro.refine_shift = w_.use_shift;
  return RefineRelpose(p_, in.reproj0, in.reproj1, in.sampson, ro, model);
}

// The last refinement with down-weighted reprojection terms (options.final_reprojection_weight): the
// depth priors have picked the hypothesis, the inliers and the focal lengths; the epipolar evidence of
// accurate matches then sets the pose, which monocular depth biases when it is distorted. Rounds of
// (refine, re-select inliers); a round is kept only if it keeps >= 95% of the epipolar inliers.
// Levenberg-Marquardt starts at the joint estimate, so directions the epipolar cost leaves flat
// (small baselines) stay close to it.
void Engine::LeanOnEpipolarEvidence(AffineDepthPose* model, double* score) {
  const bool epipolar_only = o_.final_reprojection_weight == 0.0;
  RelposeRefinerOptions ro;
  ro.max_iterations = o_.final_max_lm_iterations;
  ro.sampson_weight = w_.sampson_weight;
  ro.refine_shift = w_.use_shift;
  ro.reprojection_weight = o_.final_reprojection_weight;
  ro.refine_focal = !epipolar_only;
  const std::vector<int> none;
  for (int round = 0; round < 3; ++round) {
    AffineDepthPose refined = *model;
    if (!RefineRelpose(p_, epipolar_only ? none : inliers_.reproj0, epipolar_only ? none : inliers_.reproj1,
                       inliers_.sampson, ro, &refined)) {
      return;
    }
    if (epipolar_only) FitDepthParameters(p_, inliers_.sampson, w_.use_shift, &refined);
    InlierSets check;
    ComputeInliers(p_, refined, w_, &check);
    if (check.sampson.size() < 0.95 * inliers_.sampson.size()) return;
    const bool same_inliers = check.sampson == inliers_.sampson;
    *model = refined;
    *score = ScoreModel(p_, refined, w_);
    inliers_ = check;
    if (same_inliers) return;
  }
}

void Engine::LocalOptimize(AffineDepthPose* model, double* score, bool from_point_solver) {
  ++num_lo_;
  for (int step = 0; step < o_.num_lo_steps; ++step) {
    AffineDepthPose candidate = *model;
    ComputeInliers(p_, candidate, w_, &inliers_);
    if (from_point_solver && step == 0 && w_.use_reprojection && !inliers_.sampson.empty()) {
      // A point-solver model's scale and shifts come from its 5-7 sample points only: refit them on
      // all epipolar inliers first, then recompute the depth inliers.
      AffineDepthPose refit = candidate;
      if (FitDepthParameters(p_, inliers_.sampson, w_.use_shift, &refit) &&
          ScoreModel(p_, refit, w_) < ScoreModel(p_, candidate, w_)) {
        candidate = refit;
        ComputeInliers(p_, candidate, w_, &inliers_);
      }
    }
    if (!Refine(&candidate, inliers_, o_.lo_max_lm_iterations)) break;
    // Ties are accepted: once the inlier errors are below the rounding of the (truncated) outlier
    // terms the score stops changing, but the least-squares model is still the better one.
    const double s = ScoreModel(p_, candidate, w_);
    if (!(s <= *score)) break;
    *model = candidate;
    *score = s;
  }
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

  int it = 0;
  for (; it < o_.max_iterations; ++it) {
    if (it >= o_.min_iterations && it >= required) break;
    const double P_depth = AllInlierProbability(ratios.both_depths, k_depth);
    const double P_point = AllInlierProbability(ratios.sampson, k_point);
    double q_depth = depth_ok ? (point_ok ? FirstSolverProbability(P_depth, P_point) : 1.0) : 0.0;
    const MinimalSolverKind kind =
        sampler_.Uniform() < q_depth ? MinimalSolverKind::kDepth : MinimalSolverKind::kPoint;
    if (kind == MinimalSolverKind::kDepth) {
      sampler_.Sample(p_.with_both_depths, k_depth, sample);
      ++result.num_depth_samples;
    } else {
      sampler_.Sample(all, k_point, sample);
      ++result.num_point_samples;
    }
    solvers_.Solve(kind, sample, &models);
    bool improved = false;
    for (AffineDepthPose& m : models) {
      const double s = ScoreModel(p_, m, w_, best_score);
      if (s < best_score) {
        best_score = s;
        best = m;
        have_best = true;
        improved = true;
        if (o_.num_lo_steps > 0) LocalOptimize(&best, &best_score, kind == MinimalSolverKind::kPoint);
      }
    }
    if (improved) {
      ComputeInliers(p_, best, w_, &inliers_);
      ratios = ComputeRatios(p_, inliers_, w_);
      const double P_d = AllInlierProbability(ratios.both_depths, k_depth);
      const double P_p = AllInlierProbability(ratios.sampson, k_point);
      const double qd = depth_ok ? (point_ok ? FirstSolverProbability(P_d, P_p) : 1.0) : 0.0;
      required = RequiredIterations({qd, 1.0 - qd}, {P_d, P_p}, o_.confidence, o_.max_iterations);
    }
  }
  result.iterations = it;

  if (have_best) {
    ComputeInliers(p_, best, w_, &inliers_);
    if (o_.final_refinement) {
      // Refine on the final inliers, re-select the inliers and refine once more; keep the result
      // only if it improves the MSAC score.
      for (int round = 0; round < 2; ++round) {
        AffineDepthPose refined = best;
        if (!Refine(&refined, inliers_, o_.final_max_lm_iterations)) break;
        const double s = ScoreModel(p_, refined, w_);
        if (!(s <= best_score)) break;
        best = refined;
        best_score = s;
        ComputeInliers(p_, best, w_, &inliers_);
      }
    }
    if (o_.final_refinement && o_.final_reprojection_weight < 1.0 && w_.use_reprojection && w_.use_sampson &&
        !inliers_.sampson.empty()) {
      LeanOnEpipolarEvidence(&best, &best_score);
    }
    if (!w_.use_reprojection) {
      // Sampson-only scoring leaves scale and shifts as the sample gave them: fit them on all
      // epipolar inliers for the output.
      FitDepthParameters(p_, inliers_.sampson, w_.use_shift, &best);
    }
    result.model = best;
    result.score = best_score;
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

}  // namespace

HybridEstimate EstimateHybridRelpose(const RelposeProblem& problem, const HybridEstimatorOptions& options) {
  options.Check();
  const auto start = std::chrono::steady_clock::now();
  Engine engine(problem, options);
  HybridEstimate result = engine.Run();
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
    result.iterations += competitor.iterations;
    result.num_point_samples += competitor.num_point_samples;
    result.num_lo += competitor.num_lo;
  }
  result.runtime_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace madsfm
