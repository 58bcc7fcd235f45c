// Sampling and stopping of the hybrid RANSAC loop (Camposeco et al., "Hybrid camera pose
// estimation", CVPR 2018): each minimal solver is drawn with a probability proportional to the
// chance that its sample is all-inlier, estimated from the inlier ratios of its data types.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

namespace madsfm {

// Draws k distinct elements of a pool uniformly (k small, pool size >= k).
class IndexSampler {
 public:
  explicit IndexSampler(uint64_t seed) : rng_(seed) {}
  void Sample(const std::vector<int>& pool, int k, int* out);
  // Uniform double in [0, 1).
  double Uniform() { return std::uniform_real_distribution<double>(0.0, 1.0)(rng_); }

 private:
  std::mt19937_64 rng_;
};

// Probability that a sample of `sample_size` data drawn from data with inlier ratio `inlier_ratio`
// is all-inlier: inlier_ratio^sample_size.
double AllInlierProbability(double inlier_ratio, int sample_size);

// Probability of drawing solver 0 of two, given each solver's all-inlier probability; 0.5 while
// neither has any support yet.
double FirstSolverProbability(double p_all_inlier0, double p_all_inlier1);

// Iterations needed so that, drawing solver s with probability q_s, at least one all-inlier sample
// has been drawn with probability `confidence`: log(1 - confidence) / log(1 - sum_s q_s P_s).
// Returns max_iterations when the success probability per iteration is ~0.
int RequiredIterations(const std::vector<double>& solver_probabilities, const std::vector<double>& all_inlier,
                       double confidence, int max_iterations);

}  // namespace madsfm
