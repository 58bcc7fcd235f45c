#include "madsfm/estimators/msac_scoring.h"

#include <algorithm>
#include <cmath>

#include "madsfm/geometry/essential_matrix.h"

namespace madsfm {

ModelResiduals::ModelResiduals(const AffineDepthPose& m, double pixel_scale0, double pixel_scale1,
                               double parallel_sin2)
    : R_(m.R), Rt_(m.R.transpose()), t_(m.t), tt_(-m.R.transpose() * m.t), shift0_(m.shift0), shift1_(m.shift1),
      scale_(m.scale), f0_(m.f0), f1_(m.f1), inv_f0_(1.0 / m.f0), inv_f1_(1.0 / m.f1),
      pixel_scale0_sq_(pixel_scale0 * pixel_scale0), pixel_scale1_sq_(pixel_scale1 * pixel_scale1),
      pixel_scale01_(pixel_scale0 * pixel_scale1), parallel_sin2_(parallel_sin2) {
  // F in solver units: F = K1^-T [t]x R K0^-1 with K = diag(f, f, 1).
  const Eigen::Matrix3d E = CrossProductMatrix(m.t) * m.R;
  const Eigen::Vector3d k0(inv_f0_, inv_f0_, 1.0), k1(inv_f1_, inv_f1_, 1.0);
  F_ = k1.asDiagonal() * E * k0.asDiagonal();
  const double n = F_.norm();
  if (n > 0.0) F_ /= n;  // the Sampson error does not depend on the scale of F
  Ft_ = F_.transpose();
}

MsacWeights MsacWeights::FromOptions(const HybridEstimatorOptions& o) {
  MsacWeights w;
  w.reproj_sq = o.reproj_threshold * o.reproj_threshold;
  w.sampson_sq = o.epipolar_threshold * o.epipolar_threshold;
  w.use_reprojection = o.scoring != ScoringMode::kSampsonOnly;
  w.use_sampson = o.scoring != ScoringMode::kReprojectionOnly;
  w.sampson_weight = o.scoring == ScoringMode::kHybrid ? 2.0 * o.sampson_weight * w.reproj_sq / w.sampson_sq : 1.0;
  w.use_shift = o.estimate_shift;
  w.cheirality = o.sampson_cheirality;
  w.cheirality_min_parallax = o.cheirality_min_parallax;
  return w;
}

double MsacWeights::ParallelSin2(double focal_px0, double focal_px1) const {
  const double f = std::min(focal_px0, focal_px1);
  if (!(f > 0.0) || !(cheirality_min_parallax > 0.0)) return ModelResiduals::kParallelSin2;
  const double angle = cheirality_min_parallax * std::sqrt(sampson_sq) / f;  // sin(x) ~ x: a few mrad at most
  return std::max(ModelResiduals::kParallelSin2, angle * angle);
}

namespace {

// The error of correspondence i as Sampson data (with cheirality when the weights ask for it), capped at the
// Sampson threshold: exact below it, some value >= it above.
double CappedSampsonError(const ModelResiduals& res, const RelposeProblem& p, int i, const MsacWeights& w) {
  return w.cheirality ? res.SampsonCheiral(p.x0[i], p.x1[i], w.sampson_sq)
                      : res.Sampson(p.x0[i], p.x1[i], w.sampson_sq);
}

// The score of ScoreModel; with kCount also the inliers (into *count), and then an early stop needs, besides the
// score above stop_above, a count that can no longer exceed min_count.
template <bool kCount>
double Score(const RelposeProblem& p, const AffineDepthPose& model, const MsacWeights& w, double stop_above,
             int min_count, int* count) {
  const ModelResiduals res(model, p.pixel_scale0, p.pixel_scale1,
                           w.ParallelSin2(model.f0 * p.pixel_scale0, model.f1 * p.pixel_scale1));
  const int n = p.size();
  const int per_point = (w.use_reprojection ? 2 : 0) + (w.use_sampson ? 1 : 0);
  double score = 0.0;
  int c = 0;
  const double* d0 = p.d0.data();
  const double* d1 = p.d1.data();
  for (int i = 0; i < n; ++i) {
    if (w.use_reprojection) {
      // NaN priors (no depth) are skipped: they are not data of the reprojection types.
      if (d0[i] == d0[i]) {
        const double e = res.Reprojection01(p.x0[i], p.x1[i], d0[i], w.reproj_sq);
        if (kCount) c += e < w.reproj_sq;
        score += std::min(e, w.reproj_sq);
      }
      if (d1[i] == d1[i]) {
        const double e = res.Reprojection10(p.x0[i], p.x1[i], d1[i], w.reproj_sq);
        if (kCount) c += e < w.reproj_sq;
        score += std::min(e, w.reproj_sq);
      }
    }
    if (w.use_sampson) {
      const double e = CappedSampsonError(res, p, i, w);
      if (kCount) c += e < w.sampson_sq;
      score += w.sampson_weight * std::min(e, w.sampson_sq);
    }
    if ((i & 31) == 31 && score > stop_above && (!kCount || c + per_point * (n - 1 - i) <= min_count)) break;
  }
  if (kCount) *count = c;
  return score;
}

}  // namespace

double ScoreModel(const RelposeProblem& p, const AffineDepthPose& model, const MsacWeights& w, double stop_above) {
  return Score<false>(p, model, w, stop_above, 0, nullptr);
}

double ScoreModelCounting(const RelposeProblem& p, const AffineDepthPose& model, const MsacWeights& w, double stop_above,
                          int min_count, int* count) {
  return Score<true>(p, model, w, stop_above, min_count, count);
}

void ComputeInliers(const RelposeProblem& p, const AffineDepthPose& model, const MsacWeights& w, InlierSets* in) {
  const ModelResiduals res(model, p.pixel_scale0, p.pixel_scale1,
                           w.ParallelSin2(model.f0 * p.pixel_scale0, model.f1 * p.pixel_scale1));
  in->reproj0.clear();
  in->reproj1.clear();
  in->sampson.clear();
  for (int i = 0; i < p.size(); ++i) {
    if (w.use_reprojection) {
      const double cap = w.reproj_sq;
      if (p.d0[i] == p.d0[i] && res.Reprojection01(p.x0[i], p.x1[i], p.d0[i], cap) < cap) in->reproj0.push_back(i);
      if (p.d1[i] == p.d1[i] && res.Reprojection10(p.x0[i], p.x1[i], p.d1[i], cap) < cap) in->reproj1.push_back(i);
    }
    if (w.use_sampson) {
      if (CappedSampsonError(res, p, i, w) < w.sampson_sq) in->sampson.push_back(i);
    }
  }
}

double ScoreModelAndComputeInliers(const RelposeProblem& p, const AffineDepthPose& model, const MsacWeights& w,
                                   const MsacWeights& wi, InlierSets* in) {
  // Errors are capped at the (larger) inlier thresholds: exact below them, so exact below the score's thresholds
  // too, and >= them above (where the score takes the threshold either way).
  const double ps2 = w.ParallelSin2(model.f0 * p.pixel_scale0, model.f1 * p.pixel_scale1);
  const double ps2i = wi.ParallelSin2(model.f0 * p.pixel_scale0, model.f1 * p.pixel_scale1);
  const ModelResiduals res(model, p.pixel_scale0, p.pixel_scale1, ps2i);
  in->reproj0.clear();
  in->reproj1.clear();
  in->sampson.clear();
  double score = 0.0;
  const double* d0 = p.d0.data();
  const double* d1 = p.d1.data();
  for (int i = 0; i < p.size(); ++i) {
    if (w.use_reprojection) {
      if (d0[i] == d0[i]) {
        const double e = res.Reprojection01(p.x0[i], p.x1[i], d0[i], wi.reproj_sq);
        if (e < wi.reproj_sq) in->reproj0.push_back(i);
        score += std::min(e, w.reproj_sq);
      }
      if (d1[i] == d1[i]) {
        const double e = res.Reprojection10(p.x0[i], p.x1[i], d1[i], wi.reproj_sq);
        if (e < wi.reproj_sq) in->reproj1.push_back(i);
        score += std::min(e, w.reproj_sq);
      }
    }
    if (w.use_sampson) {
      const double e = res.Sampson(p.x0[i], p.x1[i], wi.sampson_sq);
      double e_score = e;  // SampsonCheiral under the score's parallel tolerance
      if (e < wi.sampson_sq) {
        if (!w.cheirality) {
          in->sampson.push_back(i);
        } else {
          const ModelResiduals::RayPair rays = res.Cheirality(p.x0[i], p.x1[i]);  // once for both tolerances
          if (!rays.BehindBeyond(ps2i)) in->sampson.push_back(i);
          if (e < w.sampson_sq && rays.BehindBeyond(ps2)) e_score = ModelResiduals::kInvalidError;
        }
      }
      score += w.sampson_weight * std::min(e_score, w.sampson_sq);
    }
  }
  return score;
}

}  // namespace madsfm
