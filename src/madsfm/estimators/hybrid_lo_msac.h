// The hybrid LO-MSAC engine (paper Sec. 4.4; Camposeco et al. 2018; Lebeda et al. 2012): draws the
// affine-depth solver or the point solver of the problem's camera mode, scores hypotheses with the
// hybrid MSAC score over three data types, locally optimises every new best model by joint least
// squares over the inliers of all types, stops adaptively and refines the final model.
#pragma once

#include "madsfm/estimators/hybrid_estimator_options.h"
#include "madsfm/estimators/relpose_problem.h"

namespace madsfm {

// Runs the estimator on a prepared problem. Deterministic for options.seed. Throws
// std::invalid_argument for invalid options; bad data (too few correspondences, no depth) is not
// an error: it falls back to the solvers that can run, or returns success = false.
HybridEstimate EstimateHybridRelpose(const RelposeProblem& problem, const HybridEstimatorOptions& options);

}  // namespace madsfm
