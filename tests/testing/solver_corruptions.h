// Named corruptions of a valid solver instance into degenerate input, shared by the solver tests.
#pragma once

#include <limits>

#include "testing/solver_instances.h"

namespace madsfm::testing {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
inline constexpr double kInf = std::numeric_limits<double>::infinity();

// A named change of a valid instance into a degenerate one.
struct Corruption {
  const char* name;
  bool must_be_empty;  // the solver must return 0 solutions (otherwise: 0 or valid ones)
  void (*apply)(SolverInstance*);
};

}  // namespace madsfm::testing
