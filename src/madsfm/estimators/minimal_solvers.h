// The two minimal solvers of each camera mode behind one interface (paper Sec. 4.4):
//  calibrated: affine-depth 3pt & 5pt essential; shared focal: affine-depth 4pt & 6pt;
//  two focal: affine-depth 4pt & 7pt fundamental + Bougnoux. Point-solver models get scale and
//  shifts by triangulating the sample and fitting the priors (FitAffineDepthToPose).
#pragma once

#include <vector>

#include "madsfm/estimators/relpose_problem.h"
#include "madsfm/geometry/affine_depth_pose.h"
#include "madsfm/solvers/shared_focal_6pt.h"

namespace madsfm {

enum class MinimalSolverKind { kDepth = 0, kPoint = 1 };

// Sample size of a solver in a mode (shift = false: the scale-only depth solvers).
int MinimalSampleSize(CameraMode mode, MinimalSolverKind kind, bool shift);

// Runs the solver on the correspondences `sample` (MinimalSampleSize of them) of the problem and
// appends the models that pass the problem's focal bounds. Preallocated scratch lives in the class.
class MinimalSolvers {
 public:
  MinimalSolvers(const RelposeProblem& problem, bool shift);
  // Clears *models, fills it, returns the count.
  int Solve(MinimalSolverKind kind, const int* sample, std::vector<AffineDepthPose>* models);

 private:
  int SolveDepth(std::vector<AffineDepthPose>* models);
  int SolvePoint(std::vector<AffineDepthPose>* models);
  // Turns a (R, t direction, focals) into a full model using the sample's priors.
  void AddPointModel(const Eigen::Matrix3d& E, double f0, double f1, std::vector<AffineDepthPose>* models);

  const RelposeProblem& problem_;
  bool shift_;
  std::vector<Eigen::Vector2d> x0_, x1_, n0_, n1_;
  std::vector<double> d0_, d1_;
  std::vector<Eigen::Matrix3d> matrices_;
  std::vector<FocalFundamental> focal_solutions_;
  std::vector<AffineDepthPose> scratch_;
};

// Fits scale and shifts of a model whose R, t come from points, using the given correspondences
// (e.g. all Sampson inliers). Returns false if there are too few usable priors.
bool FitDepthParameters(const RelposeProblem& problem, const std::vector<int>& indices, bool shift,
                        AffineDepthPose* model);

// The same with FitAffineDepthToPoseWeighted (priors as the regressor, parallax weights): for a final pose.
// angular_noise: matching noise in radians (e.g. 1 px / focal). max_shift0, max_shift1: bounds of |shift| per view
// in prior units (0: unbounded); beyond them the fit lies on the bound.
bool FitDepthParametersWeighted(const RelposeProblem& problem, const std::vector<int>& indices, bool shift,
                                double angular_noise, AffineDepthPose* model, double max_shift0 = 0.0,
                                double max_shift1 = 0.0);

}  // namespace madsfm
