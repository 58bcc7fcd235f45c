// Per-correspondence errors of an affine-depth model and the hybrid MSAC score (paper Sec. 4.3-4.4).
// This is the hot path of the estimator: everything per model is precomputed in ModelResiduals.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <vector>

#include "madsfm/estimators/hybrid_estimator_options.h"
#include "madsfm/estimators/relpose_problem.h"
#include "madsfm/geometry/affine_depth_pose.h"

namespace madsfm {

// Squared errors in pixels^2 of one model; a point that lands behind a camera, or a non-positive
// corrected depth, gets kInvalidError (an outlier under any threshold).
class ModelResiduals {
 public:
  static constexpr double kInvalidError = std::numeric_limits<double>::max();

  // parallel_sin2: SampsonCheiral does not judge rays whose squared sine of their angle is at most this.
  ModelResiduals(const AffineDepthPose& model, double pixel_scale0, double pixel_scale1,
                 double parallel_sin2 = kParallelSin2);

  // Lift x0 with the corrected prior d0 and reproject into view 1.
  // With `cap`, an error of at least cap may be returned as cap (see Sampson).
  double Reprojection01(const Eigen::Vector2d& x0, const Eigen::Vector2d& x1, double d0,
                        double cap = std::numeric_limits<double>::infinity()) const {
    const double z0 = d0 + shift0_;
    if (!(z0 > 0.0)) return kInvalidError;
    const Eigen::Vector3d X1 = z0 * (R_ * Eigen::Vector3d(x0.x() * inv_f0_, x0.y() * inv_f0_, 1.0)) + t_;
    if (!(X1.z() > 0.0)) return kInvalidError;
    if (BeyondCap(X1, f1_, x1, pixel_scale1_sq_, cap)) return cap;
    const double s = f1_ / X1.z();
    const double ex = X1.x() * s - x1.x(), ey = X1.y() * s - x1.y();
    return (ex * ex + ey * ey) * pixel_scale1_sq_;
  }

  // Lift x1 with the corrected prior d1 and reproject into view 0.
  double Reprojection10(const Eigen::Vector2d& x0, const Eigen::Vector2d& x1, double d1,
                        double cap = std::numeric_limits<double>::infinity()) const {
    const double z1 = scale_ * (d1 + shift1_);
    if (!(z1 > 0.0)) return kInvalidError;
    const Eigen::Vector3d X0 = z1 * (Rt_ * Eigen::Vector3d(x1.x() * inv_f1_, x1.y() * inv_f1_, 1.0)) + tt_;
    if (!(X0.z() > 0.0)) return kInvalidError;
    if (BeyondCap(X0, f0_, x0, pixel_scale0_sq_, cap)) return cap;
    const double s = f0_ / X0.z();
    const double ex = X0.x() * s - x0.x(), ey = X0.y() * s - x0.y();
    return (ex * ex + ey * ey) * pixel_scale0_sq_;
  }

  // Squared Sampson error; kInvalidError when the triangulated point lies behind either camera and its rays are
  // not nearly parallel (sin^2 of the angle between them above parallel_sin2): the Sampson error cannot tell
  // the four decompositions of an essential matrix apart, cheirality can. Nearly parallel rays (points near
  // infinity, whose depth sign is noise) are not judged.
  // An error of at least `cap` is returned as some value >= cap, neither divided out nor judged: a caller that
  // caps errors at a threshold gets the same capped value and the same inliers, without the division and the
  // cheirality test for every outlier (the hot path of the search).
  double SampsonCheiral(const Eigen::Vector2d& x0, const Eigen::Vector2d& x1,
                        double cap = std::numeric_limits<double>::infinity()) const {
    const double sampson = Sampson(x0, x1, cap);
    if (!(sampson < cap)) return sampson;
    return Cheirality(x0, x1).BehindBeyond(parallel_sin2_) ? kInvalidError : sampson;
  }
  static constexpr double kParallelSin2 = 1e-6;  // rays within ~0.06 deg of each other (the least judged)

  // The cheirality of the point triangulated from x0 and x1, to be judged under one or more parallel tolerances.
  struct RayPair {
    bool behind;      // behind either camera
    double cross_sq;  // |v1 x R v0|^2 = a c - b^2; the squared sine of the rays' angle is cross_sq / (a c)
    double a, c;      // |v1|^2, |R v0|^2
    // Behind a camera while the rays are further apart than parallel_sin2 (sin^2 of their angle): SampsonCheiral's
    // test, with any tolerance.
    bool BehindBeyond(double parallel_sin2) const { return behind && cross_sq > parallel_sin2 * a * c; }
  };
  RayPair Cheirality(const Eigen::Vector2d& x0, const Eigen::Vector2d& x1) const {
    const Eigen::Vector3d v1(x1.x() * inv_f1_, x1.y() * inv_f1_, 1.0);
    const Eigen::Vector3d Rv0 = R_ * Eigen::Vector3d(x0.x() * inv_f0_, x0.y() * inv_f0_, 1.0);
    const double a = v1.squaredNorm(), b = v1.dot(Rv0), c = Rv0.squaredNorm();
    const double e = v1.dot(t_), g = Rv0.dot(t_);
    // lambda1 v1 - lambda0 R v0 = t in the least-squares sense; both numerators carry the sign (det >= 0).
    const double num1 = c * e - b * g, num0 = b * e - a * g;
    return {num1 < 0.0 || num0 < 0.0, a * c - b * b, a, c};
  }

  // Squared Sampson error; with `cap`, an error of at least cap is returned as cap (see SampsonCheiral).
  double Sampson(const Eigen::Vector2d& x0, const Eigen::Vector2d& x1,
                 double cap = std::numeric_limits<double>::infinity()) const {
    const Eigen::Vector3d Fx0 = F_.col(0) * x0.x() + F_.col(1) * x0.y() + F_.col(2);
    const Eigen::Vector3d Ftx1 = Ft_.col(0) * x1.x() + Ft_.col(1) * x1.y() + Ft_.col(2);
    const double c = x1.x() * Fx0.x() + x1.y() * Fx0.y() + Fx0.z();
    const double denom = Fx0.x() * Fx0.x() + Fx0.y() * Fx0.y() + Ftx1.x() * Ftx1.x() + Ftx1.y() * Ftx1.y();
    // c^2 / denom * s >= cap without the division: the margin covers the rounding of both sides (a few ulps), so
    // the division below gives >= cap too whenever this holds, and capped values and inliers are unchanged.
    // (With cap = inf the test is false, or NaN for denom = 0: the exact path.)
    if (c * c * pixel_scale01_ >= cap * denom * kSampsonCapMargin) return cap;
    if (!(denom > 0.0)) return kInvalidError;
    return c * c / denom * pixel_scale01_;
  }

 private:
  // Whether the squared reprojection error of X (z > 0) against x is certainly at least cap, tested without the
  // division by z: ((X.x f - x z)^2 + (X.y f - y z)^2) s >= cap z^2. The two forms differ by rounding only, a
  // relative 1e-11 at most for image coordinates below 1e4 thresholds; kReprojCapMargin covers it many times
  // over, so errors of the exact path below the cap are never cut.
  static bool BeyondCap(const Eigen::Vector3d& X, double f, const Eigen::Vector2d& x, double s, double cap) {
    const double ex = X.x() * f - x.x() * X.z(), ey = X.y() * f - x.y() * X.z();
    return (ex * ex + ey * ey) * s >= cap * (X.z() * X.z()) * kReprojCapMargin;
  }
  static constexpr double kSampsonCapMargin = 1.0 + 1e-12;
  static constexpr double kReprojCapMargin = 1.0 + 1e-6;

  Eigen::Matrix3d R_, Rt_, F_, Ft_;
  Eigen::Vector3d t_, tt_;
  double shift0_, shift1_, scale_, f0_, f1_, inv_f0_, inv_f1_;
  double pixel_scale0_sq_, pixel_scale1_sq_, pixel_scale01_;
  double parallel_sin2_;
};

// The truncated thresholds and weights of the hybrid MSAC score.
struct MsacWeights {
  double reproj_sq = 0.0;     // tau_r^2 (pixels^2)
  double sampson_sq = 0.0;    // tau_s^2
  double sampson_weight = 0.0;  // 2 lambda_s tau_r^2 / tau_s^2 (hybrid) or 1 (Sampson-only)
  bool use_reprojection = true;
  bool use_sampson = true;
  bool use_shift = true;
  bool cheirality = true;  // Sampson data: points behind a camera are outliers (SampsonCheiral)
  double cheirality_min_parallax = 0.5;  // ... judged beyond this many Sampson-threshold angles of parallax

  // sin^2 of the parallax below which SampsonCheiral does not judge, for a model's focal lengths in pixels
  // (model f times the problem's pixel scale): (cheirality_min_parallax tau_s / f)^2, at least kParallelSin2.
  double ParallelSin2(double focal_px0, double focal_px1) const;

  static MsacWeights FromOptions(const HybridEstimatorOptions& options);
  // The same weights with both squared thresholds multiplied by `factor` (the relaxed thresholds of the local
  // optimisation); the Sampson weight stays.
  MsacWeights Relaxed(double factor) const {
    MsacWeights w = *this;
    w.reproj_sq *= factor;
    w.sampson_sq *= factor;
    return w;
  }
};

// Hybrid MSAC score of a model over all correspondences: sum of truncated reprojection errors of the
// correspondences with depth (both directions) plus the weighted truncated Sampson errors. Stops early
// and returns a value > stop_above as soon as the partial sum exceeds it.
double ScoreModel(const RelposeProblem& problem, const AffineDepthPose& model, const MsacWeights& weights,
                  double stop_above = std::numeric_limits<double>::infinity());

// The same score, also counting the inliers (errors below the thresholds, all data types together) into *count.
// Stops early (with a partial count) only when the partial score exceeds stop_above and the count can no longer
// exceed min_count: then neither the score nor the count beats them.
double ScoreModelCounting(const RelposeProblem& problem, const AffineDepthPose& model, const MsacWeights& weights,
                          double stop_above, int min_count, int* count);

// Inlier sets of the three data types (error below the squared threshold). Masks are resized to
// problem.size(); a type that is not scored gets an empty set.
struct InlierSets {
  std::vector<int> reproj0, reproj1, sampson;
  int Total() const { return static_cast<int>(reproj0.size() + reproj1.size() + sampson.size()); }
};
void ComputeInliers(const RelposeProblem& problem, const AffineDepthPose& model, const MsacWeights& weights,
                    InlierSets* inliers);

// ScoreModel(problem, model, weights) (without an early stop) and ComputeInliers(problem, model, inlier_weights,
// inliers) in one pass over the correspondences, each error computed once: the local optimisation scores every
// fitted model and then selects that model's inliers under a relaxed threshold. inlier_weights must be `weights`
// with thresholds at least as large (MsacWeights::Relaxed with a factor >= 1); both results equal the two separate
// calls.
double ScoreModelAndComputeInliers(const RelposeProblem& problem, const AffineDepthPose& model,
                                   const MsacWeights& weights, const MsacWeights& inlier_weights,
                                   InlierSets* inliers);

}  // namespace madsfm
