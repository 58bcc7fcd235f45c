// `madsfm focal_estimator`: one focal length per camera from the pairwise estimates of two_view_estimator.
#pragma once

#include <limits>
#include <string>
#include <vector>

namespace madsfm {

// A pairwise focal estimate of one camera, weighted by the pair's inliers, with its relative standard deviation
// (MadsfmPairRow::sigma_focal1/2; NaN: unknown).
struct FocalSample {
  double focal = 0.0;
  double weight = 0.0;
  double sigma = std::numeric_limits<double>::quiet_NaN();
};

struct FocalAggregate {
  double focal = 0.0;   // robust estimate (pixels)
  double spread = 0.0;  // weighted median absolute deviation of log(f) of the kept samples (~ relative spread)
  int num_used = 0;     // samples kept after outlier rejection
  int num_total = 0;
};

// Weighted median of log(f), then rejects samples more than max(3 x MAD, 5%) away from it, and returns the
// weighted mean of the kept log(f) (so the estimate is robust to wrong pairs, yet uses all good ones).
// num_used = 0 when there are no samples.
FocalAggregate AggregateFocal(const std::vector<FocalSample>& samples);

// When is an aggregated focal length trusted enough to become a prior (prior_focal_length = 1, which makes COLMAP
// prefer the camera for the initial pair and stop re-estimating its focal in absolute pose)? Only pairs estimated
// with depth priors (method 0 in madsfm_two_view_geometries) count as evidence; the point-only fallback's focal is
// ignored. A camera whose focal is trusted has at least min_prior_pairs such estimates within prior_agreement
// (relative) of the aggregate, and they are at least min_prior_fraction of all its depth-backed estimates. Cameras
// with evidence that is not trusted get the aggregate as an initial value only (prior_focal_length = 0, bundle
// adjustment and absolute pose refine it); cameras without depth-backed estimates keep COLMAP's row.
// An estimate agrees only when the pair also determines its focal: relative standard deviation (pose, scale and
// shifts free) at most prior_max_pair_sigma. Where a small baseline with little rotation lets focal length, shifts
// and translation trade off, all pairs of a scene can agree on a focal the data do not fix: on the real RGB-D frames
// of docs/benchmarks.md section 9 they agreed within 3% on a focal 5% off, each with a sigma of 0.7-1.3%, where
// the synthetic walks' pairs have 0.1-0.5%.
struct FocalEstimatorOptions {
  std::string database_path;
  bool overwrite = false;          // also cameras that already have a focal prior
  int min_num_pairs = 1;           // cameras with fewer usable (depth-backed) pairs keep their focal
  int min_prior_pairs = 5;         // trusted: at least this many depth-backed estimates agree ...
  double prior_agreement = 0.03;   // ... within this relative difference of the aggregate ...
  double min_prior_fraction = 0.5; // ... and they are at least this fraction of the camera's estimates
  double prior_max_pair_sigma = 0.0075;  // an agreeing estimate's relative standard deviation is at most this
};

struct FocalChange {
  uint32_t camera_id = 0;
  double old_focal = 0, new_focal = 0, spread = 0;
  int num_pairs = 0;      // estimates kept by AggregateFocal
  int num_samples = 0;    // depth-backed estimates of the camera
  int num_agreeing = 0;   // of which within prior_agreement of the aggregate, with sigma <= prior_max_pair_sigma
  bool updated = false;   // the focal value was written
  bool trusted = false;   // ... with prior_focal_length = 1
  bool had_prior = false;
};

std::vector<FocalChange> RunFocalEstimatorImpl(const FocalEstimatorOptions& options);

}  // namespace madsfm
