#include "madsfm/estimators/minimal_solvers.h"

#include <cmath>

#include "madsfm/geometry/essential_matrix.h"
#include "madsfm/solvers/affine_depth_fit.h"
#include "madsfm/solvers/essential_5pt.h"
#include "madsfm/solvers/fundamental_7pt.h"
#include "madsfm/solvers/relpose_affine_depth_3pt.h"
#include "madsfm/solvers/relpose_affine_depth_shared_focal_4pt.h"
#include "madsfm/solvers/relpose_affine_depth_two_focal_4pt.h"
#include "madsfm/solvers/relpose_scale_depth_3pt.h"
#include "madsfm/solvers/relpose_scale_depth_shared_focal_3pt.h"
#include "madsfm/solvers/relpose_scale_depth_two_focal_3pt.h"
#include "madsfm/solvers/shared_focal_6pt.h"

namespace madsfm {

int MinimalSampleSize(CameraMode mode, MinimalSolverKind kind, bool shift) {
  if (kind == MinimalSolverKind::kDepth) return (mode == CameraMode::kCalibrated || !shift) ? 3 : 4;
  switch (mode) {
    case CameraMode::kCalibrated: return 5;
    case CameraMode::kSharedFocal: return 6;
    case CameraMode::kTwoFocal: return 7;
  }
  return 0;
}

MinimalSolvers::MinimalSolvers(const RelposeProblem& problem, bool shift) : problem_(problem), shift_(shift) {
  for (auto* v : {&x0_, &x1_, &n0_, &n1_}) v->reserve(8);
  d0_.reserve(8);
  d1_.reserve(8);
  matrices_.reserve(16);
  scratch_.reserve(16);
}

int MinimalSolvers::Solve(MinimalSolverKind kind, const int* sample, std::vector<AffineDepthPose>* models) {
  models->clear();
  const int k = MinimalSampleSize(problem_.mode, kind, shift_);
  x0_.resize(k);
  x1_.resize(k);
  d0_.resize(k);
  d1_.resize(k);
  for (int i = 0; i < k; ++i) {
    x0_[i] = problem_.x0[sample[i]];
    x1_[i] = problem_.x1[sample[i]];
    d0_[i] = problem_.d0[sample[i]];
    d1_[i] = problem_.d1[sample[i]];
  }
  return kind == MinimalSolverKind::kDepth ? SolveDepth(models) : SolvePoint(models);
}

int MinimalSolvers::SolveDepth(std::vector<AffineDepthPose>* models) {
  switch (problem_.mode) {
    case CameraMode::kCalibrated:
      shift_ ? SolveRelposeAffineDepth3pt(x0_, x1_, d0_, d1_, &scratch_)
             : SolveRelposeScaleDepth3pt(x0_, x1_, d0_, d1_, &scratch_);
      break;
    case CameraMode::kSharedFocal:
      shift_ ? SolveRelposeAffineDepthSharedFocal4pt(x0_, x1_, d0_, d1_, &scratch_)
             : SolveRelposeScaleDepthSharedFocal3pt(x0_, x1_, d0_, d1_, &scratch_);
      break;
    case CameraMode::kTwoFocal:
      shift_ ? SolveRelposeAffineDepthTwoFocal4pt(x0_, x1_, d0_, d1_, &scratch_)
             : SolveRelposeScaleDepthTwoFocal3pt(x0_, x1_, d0_, d1_, &scratch_);
      break;
  }
  for (const AffineDepthPose& m : scratch_) {
    if (problem_.mode != CameraMode::kCalibrated &&
        !(m.f0 >= problem_.min_focal && m.f0 <= problem_.max_focal && m.f1 >= problem_.min_focal &&
          m.f1 <= problem_.max_focal)) {
      continue;
    }
    models->push_back(m);
  }
  return static_cast<int>(models->size());
}

void MinimalSolvers::AddPointModel(const Eigen::Matrix3d& E, double f0, double f1,
                                   std::vector<AffineDepthPose>* models) {
  if (problem_.mode != CameraMode::kCalibrated &&
      !(f0 >= problem_.min_focal && f0 <= problem_.max_focal && f1 >= problem_.min_focal && f1 <= problem_.max_focal)) {
    return;
  }
  const int k = static_cast<int>(x0_.size());
  n0_.resize(k);
  n1_.resize(k);
  for (int i = 0; i < k; ++i) {
    n0_[i] = x0_[i] / f0;
    n1_[i] = x1_[i] / f1;
  }
  AffineDepthPose m;
  if (!PoseFromEssential(E, n0_, n1_, &m.R, &m.t)) return;
  m.f0 = f0;
  m.f1 = f1;
  // Scale and shifts from the sample's priors; without usable priors the model keeps scale 1,
  // shifts 0 and a unit translation (its reprojection errors then count as outliers until the
  // local optimisation refits the depth parameters on all inliers).
  FitAffineDepthToPose(n0_, n1_, d0_, d1_, &m, shift_);
  models->push_back(m);
}

int MinimalSolvers::SolvePoint(std::vector<AffineDepthPose>* models) {
  switch (problem_.mode) {
    case CameraMode::kCalibrated:
      SolveEssential5pt(x0_, x1_, &matrices_);
      for (const Eigen::Matrix3d& E : matrices_) AddPointModel(E, 1.0, 1.0, models);
      break;
    case CameraMode::kSharedFocal: {
      SolveSharedFocal6pt(x0_, x1_, &focal_solutions_);
      for (const FocalFundamental& s : focal_solutions_) {
        const Eigen::Vector3d k(s.f0, s.f0, 1.0);
        AddPointModel(k.asDiagonal() * s.F * k.asDiagonal(), s.f0, s.f0, models);
      }
      break;
    }
    case CameraMode::kTwoFocal:
      SolveFundamental7pt(x0_, x1_, &matrices_);
      for (const Eigen::Matrix3d& F : matrices_) {
        double f0, f1;
        if (!BougnouxFocals(F, &f0, &f1)) continue;
        const Eigen::Vector3d k0(f0, f0, 1.0), k1(f1, f1, 1.0);
        AddPointModel(k1.asDiagonal() * F * k0.asDiagonal(), f0, f1, models);
      }
      break;
  }
  return static_cast<int>(models->size());
}

namespace {

void GatherNormalised(const RelposeProblem& p, const std::vector<int>& indices, const AffineDepthPose& model,
                      std::vector<Eigen::Vector2d>* n0, std::vector<Eigen::Vector2d>* n1, std::vector<double>* d0,
                      std::vector<double>* d1) {
  for (auto* v : {n0, n1}) v->clear(), v->reserve(indices.size());
  for (auto* v : {d0, d1}) v->clear(), v->reserve(indices.size());
  for (int i : indices) {
    n0->push_back(p.x0[i] / model.f0);
    n1->push_back(p.x1[i] / model.f1);
    d0->push_back(p.d0[i]);
    d1->push_back(p.d1[i]);
  }
}

}  // namespace

bool FitDepthParametersWeighted(const RelposeProblem& p, const std::vector<int>& indices, bool shift,
                                double angular_noise, AffineDepthPose* model, double max_shift0,
                                double max_shift1) {
  std::vector<Eigen::Vector2d> n0, n1;
  std::vector<double> d0, d1;
  GatherNormalised(p, indices, *model, &n0, &n1, &d0, &d1);
  return FitAffineDepthToPoseWeighted(n0, n1, d0, d1, angular_noise, model, shift, 0.03, max_shift0, max_shift1);
}

bool FitDepthParameters(const RelposeProblem& p, const std::vector<int>& indices, bool shift, AffineDepthPose* model) {
  std::vector<Eigen::Vector2d> n0, n1;
  std::vector<double> d0, d1;
  n0.reserve(indices.size());
  n1.reserve(indices.size());
  d0.reserve(indices.size());
  d1.reserve(indices.size());
  for (int i : indices) {
    n0.push_back(p.x0[i] / model->f0);
    n1.push_back(p.x1[i] / model->f1);
    d0.push_back(p.d0[i]);
    d1.push_back(p.d1[i]);
  }
  return FitAffineDepthToPose(n0, n1, d0, d1, model, shift);
}

}  // namespace madsfm
