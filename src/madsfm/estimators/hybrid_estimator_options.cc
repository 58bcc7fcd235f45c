#include "madsfm/estimators/hybrid_estimator_options.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace madsfm {
namespace {

void Require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("invalid estimator option: " + what);
}

}  // namespace

void HybridEstimatorOptions::Check() const {
  Require(std::isfinite(reproj_threshold) && reproj_threshold > 0, "reproj_threshold must be > 0");
  Require(std::isfinite(epipolar_threshold) && epipolar_threshold > 0, "epipolar_threshold must be > 0");
  Require(std::isfinite(sampson_weight) && sampson_weight >= 0, "sampson_weight must be >= 0");
  Require(min_iterations >= 0, "min_iterations must be >= 0");
  Require(min_iterations_two_focal_points >= 0, "min_iterations_two_focal_points must be >= 0");
  Require(min_iterations_shared_focal_points >= 0, "min_iterations_shared_focal_points must be >= 0");
  Require(max_iterations >= 1, "max_iterations must be >= 1");
  Require(max_iterations >= min_iterations, "max_iterations must be >= min_iterations");
  Require(confidence > 0 && confidence < 1, "confidence must be in (0, 1)");
  Require(guided_sampling_fraction >= 0 && guided_sampling_fraction < 1, "guided_sampling_fraction must be in [0, 1)");
  Require(num_lo_steps >= 0, "num_lo_steps must be >= 0");
  Require(lo_max_lm_iterations >= 0, "lo_max_lm_iterations must be >= 0");
  Require(lo_max_lm_iterations_two_focal >= 0, "lo_max_lm_iterations_two_focal must be >= 0");
  Require(num_lo_lsq_steps >= 1, "num_lo_lsq_steps must be >= 1");
  Require(std::isfinite(lo_threshold_multiplier) && lo_threshold_multiplier >= 1,
          "lo_threshold_multiplier must be >= 1");
  Require(lo_inner_sample_multiplier >= 1, "lo_inner_sample_multiplier must be >= 1");
  Require(lo_lsq_sample_size >= 8, "lo_lsq_sample_size must be >= 8");
  Require(lo_first_fit_sample_size == 0 || lo_first_fit_sample_size >= 8,
          "lo_first_fit_sample_size must be 0 (all inliers) or >= 8");
  Require(lo_starting_iterations >= 0, "lo_starting_iterations must be >= 0");
  Require(std::isfinite(alt_basin_lo_margin) && alt_basin_lo_margin >= 0.0, "alt_basin_lo_margin must be >= 0");
  Require(planar_twin_min_support >= 0.0 && planar_twin_min_support <= 1.0,
          "planar_twin_min_support must be in [0, 1]");
  Require(std::isfinite(low_parallax_sampson_factor) && low_parallax_sampson_factor > 0.0 &&
              low_parallax_sampson_factor <= 1.0,
          "low_parallax_sampson_factor must be in (0, 1]");
  Require(std::isfinite(low_parallax_noise_ratio) && low_parallax_noise_ratio >= 0.0,
          "low_parallax_noise_ratio must be >= 0");
  Require(std::isfinite(max_shift_ratio) && max_shift_ratio >= 0, "max_shift_ratio must be >= 0");
  Require(std::isfinite(cheirality_min_parallax) && cheirality_min_parallax >= 0,
          "cheirality_min_parallax must be >= 0");
  Require(max_depth_sigma > 0, "max_depth_sigma must be > 0");
  Require(final_reprojection_weight >= 0 && final_reprojection_weight <= 1,
          "final_reprojection_weight must be in [0, 1]");
  Require(low_parallax_final_reprojection_weight >= 0 && low_parallax_final_reprojection_weight <= 1,
          "low_parallax_final_reprojection_weight must be in [0, 1]");
  Require(epipolar_check_ratio == 0 || epipolar_check_ratio >= 1, "epipolar_check_ratio must be 0 or >= 1");
  Require(std::isfinite(final_cauchy_ratio) && final_cauchy_ratio >= 0, "final_cauchy_ratio must be >= 0");
  Require(std::isfinite(epipolar_focal_max_sigma) && epipolar_focal_max_sigma >= 0,
          "epipolar_focal_max_sigma must be >= 0");
  Require(std::isfinite(epipolar_focal_wide_sigma) && epipolar_focal_wide_sigma >= 0,
          "epipolar_focal_wide_sigma must be >= 0");
  Require(final_max_lm_iterations >= 0, "final_max_lm_iterations must be >= 0");
  Require(!(solvers == SolverChoice::kDepthOnly && scoring == ScoringMode::kSampsonOnly),
          "the depth-only solver needs depth residuals in the score");
}

}  // namespace madsfm
