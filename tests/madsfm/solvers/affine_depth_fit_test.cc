#include "madsfm/solvers/affine_depth_fit.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include "madsfm/geometry/triangulation.h"
#include "testing/solver_instances.h"

namespace madsfm {
namespace {

using testing::CameraSetup;
using testing::MakeSolverInstance;
using testing::ModelError;
using testing::SolverInstance;
using testing::SolverInstanceOptions;

// The true R with the true translation direction at an arbitrary length, wrong depth parameters.
AffineDepthPose StartingModel(const SolverInstance& inst, double t_length) {
  AffineDepthPose m;
  m.R = inst.gt.R;
  m.t = inst.gt.t.normalized() * t_length;
  m.scale = 3.0;
  m.shift0 = m.shift1 = -1.0;
  m.f0 = inst.gt.f0;
  m.f1 = inst.gt.f1;
  return m;
}

// The fits work in normalised coordinates: pixel coordinates divided by the true focal lengths.
void Normalise(SolverInstance* inst) {
  for (auto& x : inst->x0) x /= inst->gt.f0;
  for (auto& x : inst->x1) x /= inst->gt.f1;
}

void RunRecovery(CameraSetup setup, bool with_shift, bool fit_shift, unsigned seed, const char* label) {
  std::mt19937 rng(seed);
  SolverInstanceOptions opt;
  opt.setup = setup;
  opt.with_shift = with_shift;
  const int kTrials = 1000;
  int ok = 0;
  double worst = 0.0;
  for (int trial = 0; trial < kTrials; ++trial) {
    opt.num_points = 5 + trial % 16;  // 5..20
    SolverInstance inst = MakeSolverInstance(rng, opt);
    Normalise(&inst);
    AffineDepthPose model = StartingModel(inst, trial % 2 ? 1.0 : 17.5);
    ASSERT_TRUE(FitAffineDepthToPose(inst.x0, inst.x1, inst.d0, inst.d1, &model, fit_shift)) << "trial " << trial;
    EXPECT_EQ(model.R, inst.gt.R);
    EXPECT_EQ(model.f0, inst.gt.f0);
    const double err = ModelError(model, inst);
    worst = std::max(worst, err);
    if (err < 1e-8) ++ok;
  }
  std::printf("[affine fit %s] scale, shifts and t recovered to 1e-8 in %d / %d instances (worst error %.2e)\n", label,
              ok, kTrials, worst);
  EXPECT_EQ(ok, kTrials);
}

TEST(AffineDepthFit, RecoversScaleShiftsAndTranslation) {
  RunRecovery(CameraSetup::kCalibrated, true, true, 1, "calibrated, shifts");
}

TEST(AffineDepthFit, RecoversTwoFocalInstancesInNormalisedCoordinates) {
  RunRecovery(CameraSetup::kTwoFocal, true, true, 2, "two-focal, shifts");
}

TEST(AffineDepthFit, ScaleOnlyModeOnShiftFreeData) {
  RunRecovery(CameraSetup::kCalibrated, false, false, 3, "scale only");
}

TEST(AffineDepthFit, ShiftFitOnShiftFreeDataGivesZeroShifts) {
  RunRecovery(CameraSetup::kCalibrated, false, true, 4, "shift-free data, shifts fitted");
}

TEST(AffineDepthFit, UsesPriorsOfEachViewSeparately) {
  // Missing priors (NaN) in one view still let that point constrain the other view.
  std::mt19937 rng(5);
  SolverInstanceOptions opt;
  opt.num_points = 6;
  const SolverInstance inst = MakeSolverInstance(rng, opt);
  std::vector<double> d0 = inst.d0, d1 = inst.d1;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  d0[0] = d0[1] = d0[2] = d0[3] = nan;  // view 0: points 4, 5
  d1[2] = d1[3] = d1[4] = d1[5] = nan;  // view 1: points 0, 1
  AffineDepthPose model = StartingModel(inst, 1.0);
  ASSERT_TRUE(FitAffineDepthToPose(inst.x0, inst.x1, d0, d1, &model));
  EXPECT_LT(ModelError(model, inst), 1e-8);
  // One prior fewer in view 0: not determined.
  d0[4] = nan;
  model = StartingModel(inst, 1.0);
  const AffineDepthPose before = model;
  EXPECT_FALSE(FitAffineDepthToPose(inst.x0, inst.x1, d0, d1, &model));
  EXPECT_EQ(model.t, before.t);  // untouched
  EXPECT_EQ(model.scale, before.scale);
  EXPECT_EQ(model.shift0, before.shift0);
}

TEST(AffineDepthFit, IgnoresPointsBehindTheCameras) {
  std::mt19937 rng(6);
  SolverInstanceOptions opt;
  opt.num_points = 8;
  SolverInstance inst = MakeSolverInstance(rng, opt);
  // Mirror the correspondence of two points so they triangulate behind a camera; their priors
  // are garbage and must be ignored.
  AffineDepthPose model = StartingModel(inst, 2.0);
  std::vector<Eigen::Vector2d> x0 = inst.x0, x1 = inst.x1;
  std::vector<double> d0 = inst.d0, d1 = inst.d1;
  const Eigen::Vector3d X(0.1, -0.05, -5.0);  // behind camera 0
  x0.push_back(X.hnormalized());
  x1.push_back((inst.gt.R * X + inst.gt.t).hnormalized());
  d0.push_back(1e3);
  d1.push_back(1e3);
  ASSERT_TRUE(FitAffineDepthToPose(x0, x1, d0, d1, &model));
  EXPECT_LT(ModelError(model, inst), 1e-8);
}

// The weighted regression is a Huber fit: iterated until it settles, it recovers exact priors when a fifth of the
// triangulated depths are grossly wrong (the points moved along the first view's ray by a factor 1.3-2).
// Four fixed reweighting rounds (madsfm-21) stopped short of it.
TEST(AffineDepthFit, WeightedFitReachesTheHuberFitDespiteGrossDepthErrors) {
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> factor(1.3, 2.0);
  SolverInstanceOptions opt;
  opt.num_points = 60;
  const int kTrials = 200;
  int ok = 0;
  double worst = 0.0;
  for (int trial = 0; trial < kTrials; ++trial) {
    SolverInstance inst = MakeSolverInstance(rng, opt);
    Normalise(&inst);
    for (int i = 0; i < opt.num_points; i += 5) {
      // The point moved along the first view's ray: the priors no longer fit its triangulated depths.
      double z0, z1;
      ASSERT_TRUE(TriangulateDepths(inst.gt.R, inst.gt.t, inst.x0[i], inst.x1[i], &z0, &z1));
      const Eigen::Vector3d moved = inst.gt.R * (factor(rng) * z0 * inst.x0[i].homogeneous()) + inst.gt.t;
      inst.x1[i] = moved.hnormalized();
    }
    AffineDepthPose model = StartingModel(inst, trial % 2 ? 1.0 : 17.5);
    ASSERT_TRUE(FitAffineDepthToPoseWeighted(inst.x0, inst.x1, inst.d0, inst.d1, 1e-3, &model)) << "trial " << trial;
    EXPECT_EQ(model.R, inst.gt.R);
    const double err = ModelError(model, inst);
    worst = std::max(worst, err);
    if (err < 1e-4) ++ok;
  }
  std::printf("[weighted affine fit] recovered to 1e-4 despite 20%% gross depth errors in %d / %d instances (worst "
              "%.2e)\n", ok, kTrials, worst);
  EXPECT_GE(ok, kTrials * 95 / 100);
}

// Median |(d0 + shift0) / z0 - 1| of view 0, z0 triangulated with the model's R and t (the corrected prior against
// the depth the model's geometry gives).
double View0Misfit(const SolverInstance& inst, const AffineDepthPose& m) {
  std::vector<double> err;
  for (size_t i = 0; i < inst.x0.size(); ++i) {
    double z0, z1;
    if (TriangulateDepths(m.R, m.t, inst.x0[i], inst.x1[i], &z0, &z1)) {
      err.push_back(std::abs(m.Depth0(inst.d0[i]) / z0 - 1.0));
    }
  }
  std::nth_element(err.begin(), err.begin() + err.size() / 2, err.end());
  return err[err.size() / 2];
}

// A shift bound the truth respects changes nothing: exact priors are recovered as without it.
TEST(AffineDepthFit, WeightedFitInsideTheShiftBoundIsTheFreeFit) {
  std::mt19937 rng(9);
  SolverInstanceOptions opt;
  opt.num_points = 30;
  const int kTrials = 200;
  int ok = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    SolverInstance inst = MakeSolverInstance(rng, opt);
    Normalise(&inst);
    AffineDepthPose model = StartingModel(inst, 1.0);
    const double b0 = 1.5 * std::abs(inst.gt.shift0) + 1e-3, b1 = 1.5 * std::abs(inst.gt.shift1) + 1e-3;
    ASSERT_TRUE(FitAffineDepthToPoseWeighted(inst.x0, inst.x1, inst.d0, inst.d1, 1e-3, &model, true, 0.03, b0, b1));
    if (ModelError(model, inst) < 1e-8) ++ok;
  }
  EXPECT_EQ(ok, kTrials);
}

// Beyond the bound, the regression is the best line on the bound's edge (madsfm-23): |shift| at the bound, on the
// truth's side, and the corrected priors closer to the triangulated depths than the scale-only fit (shift 0) that
// depth fits beyond the bound used to fall back to. The other view's fit is not touched.
TEST(AffineDepthFit, WeightedFitBeyondTheShiftBoundLiesOnItsEdge) {
  std::mt19937 rng(10);
  SolverInstanceOptions opt;
  opt.num_points = 30;
  opt.depth_noise = 0.01;
  const int kTrials = 200;
  int trials = 0, on_edge = 0, truth_side = 0, better_than_scale_only = 0, better_than_cut = 0;
  while (trials < kTrials) {
    SolverInstance inst = MakeSolverInstance(rng, opt);
    if (std::abs(inst.gt.shift0) < 0.2 * inst.median_depth) continue;  // a shift the bound can cut clearly
    ++trials;
    Normalise(&inst);
    const double bound0 = 0.5 * std::abs(inst.gt.shift0);
    AffineDepthPose bounded = StartingModel(inst, 1.0), free = bounded, scale_only = bounded;
    ASSERT_TRUE(FitAffineDepthToPoseWeighted(inst.x0, inst.x1, inst.d0, inst.d1, 1e-3, &free));
    ASSERT_TRUE(FitAffineDepthToPoseWeighted(inst.x0, inst.x1, inst.d0, inst.d1, 1e-3, &scale_only, false));
    ASSERT_TRUE(
        FitAffineDepthToPoseWeighted(inst.x0, inst.x1, inst.d0, inst.d1, 1e-3, &bounded, true, 0.03, bound0, 0.0));
    EXPECT_LE(std::abs(bounded.shift0), bound0 * (1.0 + 1e-12));
    on_edge += std::abs(bounded.shift0) >= bound0 * (1.0 - 1e-9);
    truth_side += (bounded.shift0 > 0.0) == (inst.gt.shift0 > 0.0);
    better_than_scale_only += View0Misfit(inst, bounded) < View0Misfit(inst, scale_only);
    // The free fit with its shift merely cut to the bound is no match for the best line on the edge either.
    AffineDepthPose cut = free;
    cut.shift0 = std::copysign(bound0, free.shift0);
    better_than_cut += View0Misfit(inst, bounded) < View0Misfit(inst, cut);
    // View 1 is fitted on its own: the same shift and the same |t| / scale as without the bound.
    EXPECT_NEAR(bounded.shift1, free.shift1, 1e-9 * inst.median_depth);
    EXPECT_NEAR(bounded.t.norm() / bounded.scale, free.t.norm() / free.scale, 1e-9 * free.t.norm() / free.scale);
  }
  std::printf("[weighted affine fit, shift bound at half the true shift] on the edge %d, on the truth's side %d, "
              "closer than the scale-only fit %d, than the cut free fit %d, of %d\n", on_edge, truth_side,
              better_than_scale_only, better_than_cut, kTrials);
  EXPECT_EQ(on_edge, kTrials);
  EXPECT_GE(truth_side, kTrials * 95 / 100);
  EXPECT_GE(better_than_scale_only, kTrials * 95 / 100);
  EXPECT_GE(better_than_cut, kTrials * 95 / 100);
}

TEST(AffineDepthFit, DegenerateCasesReturnFalse) {
  std::mt19937 rng(7);
  SolverInstanceOptions opt;
  opt.num_points = 5;
  const SolverInstance inst = MakeSolverInstance(rng, opt);
  const double nan = std::numeric_limits<double>::quiet_NaN();

  // Fewer than 2 points.
  AffineDepthPose model = StartingModel(inst, 1.0);
  EXPECT_FALSE(FitAffineDepthToPose({inst.x0[0]}, {inst.x1[0]}, {inst.d0[0]}, {inst.d1[0]}, &model));
  EXPECT_FALSE(FitAffineDepthToPose({}, {}, {}, {}, &model));
  // No priors.
  EXPECT_FALSE(FitAffineDepthToPose(inst.x0, inst.x1, std::vector<double>(5, nan), inst.d1, &model));
  // Zero or non-finite translation.
  model.t.setZero();
  EXPECT_FALSE(FitAffineDepthToPose(inst.x0, inst.x1, inst.d0, inst.d1, &model));
  model.t = Eigen::Vector3d(nan, 0.0, 0.0);
  EXPECT_FALSE(FitAffineDepthToPose(inst.x0, inst.x1, inst.d0, inst.d1, &model));
  // Every point behind the cameras: the translation direction flipped.
  model = StartingModel(inst, -1.0);
  EXPECT_FALSE(FitAffineDepthToPose(inst.x0, inst.x1, inst.d0, inst.d1, &model));
  // Priors that decrease with the true depth: negative scale factor k.
  std::vector<double> reversed(5);
  for (int i = 0; i < 5; ++i) reversed[i] = 100.0 - inst.gt.Depth0(inst.d0[i]);
  model = StartingModel(inst, 1.0);
  EXPECT_FALSE(FitAffineDepthToPose(inst.x0, inst.x1, reversed, inst.d1, &model));
  // All priors of a view at the same depth (points on a fronto-parallel plane): the shift is not
  // determined; z0 identical for all points -> no unique fit.
  const Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  const Eigen::Vector3d t(-0.3, 0.0, 0.0);
  std::vector<Eigen::Vector2d> p0, p1;
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3d X(0.2 * i - 0.3, 0.1 * i, 4.0);
    p0.push_back(X.hnormalized());
    p1.push_back((R * X + t).hnormalized());
  }
  AffineDepthPose plane;
  plane.R = R;
  plane.t = t;
  EXPECT_FALSE(FitAffineDepthToPose(p0, p1, {4.0, 4.0, 4.0, 4.0}, {4.0, 4.0, 4.0, 4.0}, &plane));
  // ... while the scale-only fit is well defined there.
  EXPECT_TRUE(FitAffineDepthToPose(p0, p1, {2.0, 2.0, 2.0, 2.0}, {8.0, 8.0, 8.0, 8.0}, &plane, false));
  EXPECT_NEAR(plane.t.norm(), 0.15, 1e-12);  // corrected depth 2 for true depth 4: |t| = 0.3 / 2
  EXPECT_NEAR(plane.scale, 0.25, 1e-12);    // corrected depth 2 in both views = scale * 8
  EXPECT_EQ(plane.shift0, 0.0);
  EXPECT_EQ(plane.shift1, 0.0);
}

}  // namespace
}  // namespace madsfm
