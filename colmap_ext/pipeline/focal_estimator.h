// `madsfm focal_estimator`: one focal length per camera from the pairwise estimates of two_view_estimator.
#pragma once

#include <string>
#include <vector>

namespace madsfm {

// A pairwise focal estimate of one camera, weighted by the pair's inliers.
struct FocalSample {
  double focal = 0.0;
  double weight = 0.0;
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

struct FocalEstimatorOptions {
  std::string database_path;
  bool overwrite = false;  // also cameras that already have a focal prior
  int min_num_pairs = 1;   // cameras with fewer usable pairs keep their focal
};

struct FocalChange {
  uint32_t camera_id = 0;
  double old_focal = 0, new_focal = 0, spread = 0;
  int num_pairs = 0;
  bool updated = false;
  bool had_prior = false;
};

std::vector<FocalChange> RunFocalEstimatorImpl(const FocalEstimatorOptions& options);

}  // namespace madsfm
