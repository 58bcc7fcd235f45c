// Builds an estimator problem from a random solver instance (tests only).
#pragma once

#include "madsfm/estimators/relpose_problem.h"
#include "testing/solver_instances.h"

namespace madsfm::testing {

inline CameraMode ModeOf(CameraSetup setup) {
  switch (setup) {
    case CameraSetup::kCalibrated: return CameraMode::kCalibrated;
    case CameraSetup::kSharedFocal: return CameraMode::kSharedFocal;
    case CameraSetup::kTwoFocal: return CameraMode::kTwoFocal;
  }
  return CameraMode::kCalibrated;
}

inline RelposeProblem ProblemFromInstance(const SolverInstance& inst, CameraSetup setup) {
  RelposeProblem p;
  p.mode = ModeOf(setup);
  p.x0 = inst.x0;
  p.x1 = inst.x1;
  p.d0 = inst.d0;
  p.d1 = inst.d1;
  if (setup == CameraSetup::kCalibrated) {
    p.pixel_scale0 = inst.focal0;
    p.pixel_scale1 = inst.focal1;
  }
  p.IndexDepths();
  return p;
}

}  // namespace madsfm::testing
