#include "madsfm/estimators/hybrid_sampling.h"

#include <algorithm>
#include <cmath>

#include "madsfm/geometry/portable_math.h"

namespace madsfm {

void IndexSampler::Sample(const std::vector<int>& pool, int k, int* out) {
  const int n = static_cast<int>(pool.size());
  for (int i = 0; i < k; ++i) {
    for (;;) {
      const int j = static_cast<int>(std::uniform_int_distribution<int>(0, n - 1)(rng_));
      bool dup = false;
      for (int l = 0; l < i; ++l) dup |= out[l] == pool[j];
      if (!dup) {
        out[i] = pool[j];
        break;
      }
    }
  }
}

double AllInlierProbability(double inlier_ratio, int sample_size) {
  return portable::PowInt(std::clamp(inlier_ratio, 0.0, 1.0), sample_size);
}

double FirstSolverProbability(double p0, double p1) {
  if (!(p0 + p1 > 0.0)) return 0.5;
  return p0 / (p0 + p1);
}

int RequiredIterations(const std::vector<double>& q, const std::vector<double>& P, double confidence,
                       int max_iterations) {
  double success = 0.0;
  for (size_t s = 0; s < q.size(); ++s) success += q[s] * P[s];
  if (success >= 1.0) return 1;
  if (!(success > 1e-12)) return max_iterations;
  const double n = portable::Log(1.0 - confidence) / portable::Log(1.0 - success);  // CPU-independent
  if (!(n < max_iterations)) return max_iterations;
  return std::max(1, static_cast<int>(std::ceil(n)));
}

}  // namespace madsfm
