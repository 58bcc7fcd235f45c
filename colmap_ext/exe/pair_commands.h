// `madsfm pair` (one pair directory -> JSON) and `madsfm bench` (many pairs -> tables, CSV, JSON).
#pragma once

#include <string>
#include <vector>

#include "madsfm/estimators/pair_evaluation.h"

namespace madsfm {

int RunPair(int argc, char** argv);
int RunBench(int argc, char** argv);

// Aggregate statistics of one method over many runs (what `bench` prints and writes to summary.json).
struct MethodSummary {
  std::string method;
  int runs = 0;
  int failures = 0;
  double median_rot_err = 0, median_trans_err = 0, median_focal_err = 0;
  std::vector<double> auc;  // at the thresholds below
  std::vector<double> auc_thresholds;
  double median_runtime_ms = 0, mean_runtime_ms = 0;
  bool has_ground_truth = false;
  bool has_focal = false;
  double share_pose_err_above_5 = 0;  // runs whose max(rot, trans) error exceeds 5 deg (failures included)
  // Depth corrections (runs measured against true depth maps): how many, the share within 1.25x of the best
  // per-view affine fit's error, the median error, and the runs with |shift| > 10x the median prior depth.
  int depth_measured = 0;
  double depth_within_125 = 0, median_depth_err = 0, median_depth_err_oracle = 0;
  int absurd_shifts = 0;
  // Of the measured runs: the share the estimator flagged depth_observable, and the share within 1.25x of the
  // oracle among those (what a user who trusts the flag gets).
  double depth_observable_share = 0, depth_within_125_observable = 0;
};
MethodSummary Summarize(const std::string& method, const std::vector<PairResult>& results, bool two_focal);

}  // namespace madsfm
