#include "colmap_ext/pipeline/focal_estimator.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>

#include "colmap_ext/database/database.h"
#include "madsfm/estimators/relpose_problem.h"

namespace madsfm {
namespace {

double WeightedMedian(std::vector<std::pair<double, double>> v) {  // (value, weight)
  std::sort(v.begin(), v.end());
  double total = 0.0;
  for (const auto& e : v) total += e.second;
  double acc = 0.0;
  for (const auto& e : v) {
    acc += e.second;
    if (acc >= 0.5 * total) return e.first;
  }
  return v.back().first;
}

}  // namespace

FocalAggregate AggregateFocal(const std::vector<FocalSample>& samples) {
  FocalAggregate a;
  a.num_total = static_cast<int>(samples.size());
  std::vector<std::pair<double, double>> logs;
  for (const FocalSample& s : samples) {
    if (s.focal > 0.0 && std::isfinite(s.focal) && s.weight > 0.0) logs.push_back({std::log(s.focal), s.weight});
  }
  if (logs.empty()) return a;
  const double med = WeightedMedian(logs);
  std::vector<std::pair<double, double>> dev;
  for (const auto& e : logs) dev.push_back({std::abs(e.first - med), e.second});
  const double mad = WeightedMedian(dev);
  const double limit = std::max(3.0 * 1.4826 * mad, std::log(1.05));
  double sum = 0.0, wsum = 0.0;
  std::vector<std::pair<double, double>> kept;
  for (const auto& e : logs) {
    if (std::abs(e.first - med) <= limit) {
      sum += e.first * e.second;
      wsum += e.second;
      kept.push_back(e);
    }
  }
  const double mean = sum / wsum;
  std::vector<std::pair<double, double>> kdev;
  for (const auto& e : kept) kdev.push_back({std::abs(e.first - mean), e.second});
  a.focal = std::exp(mean);
  a.spread = 1.4826 * WeightedMedian(kdev);
  a.num_used = static_cast<int>(kept.size());
  return a;
}

std::vector<FocalChange> RunFocalEstimatorImpl(const FocalEstimatorOptions& options) {
  auto db = colmap::Database::Open(options.database_path);
  const auto cameras = db->ReadCameras();
  std::map<colmap::image_t, colmap::camera_t> camera_of;
  for (const auto& im : db->ReadImages()) camera_of[im.image_id] = im.camera_id;
  std::map<colmap::camera_t, std::vector<FocalSample>> samples;
  for (const colmap::MadsfmPairRow& row : db->ReadMadsfmPairs()) {
    // Only pairs estimated with depth priors are evidence (the point-only fallback's focal is not trusted).
    if (row.status != 0 || row.method != 0 || row.camera_mode == static_cast<int>(CameraMode::kCalibrated)) continue;
    colmap::image_t i1, i2;
    colmap::PairIdToImagePair(row.pair_id, &i1, &i2);
    const double w = row.num_inliers;
    if (row.camera_mode == static_cast<int>(CameraMode::kSharedFocal) && camera_of[i1] == camera_of[i2]) {
      samples[camera_of[i1]].push_back({row.focal1, w, row.sigma_focal1});
    } else {
      samples[camera_of[i1]].push_back({row.focal1, w, row.sigma_focal1});
      samples[camera_of[i2]].push_back({row.focal2, w, row.sigma_focal2});
    }
  }
  std::vector<FocalChange> changes;
  colmap::Database::Transaction txn(db.get());
  for (const colmap::Camera& cam : cameras) {
    FocalChange c;
    c.camera_id = cam.camera_id;
    c.old_focal = c.new_focal = cam.intrinsics.FocalX();
    c.had_prior = cam.prior_focal_length;
    const std::vector<FocalSample>& cam_samples = samples[cam.camera_id];
    const FocalAggregate a = AggregateFocal(cam_samples);
    c.num_pairs = a.num_used;
    c.spread = a.spread;
    c.num_samples = static_cast<int>(cam_samples.size());
    for (const FocalSample& s : cam_samples) {
      // (NaN sigma, a row of an older madsfm: not counted.)
      c.num_agreeing += a.focal > 0 && std::abs(s.focal / a.focal - 1.0) <= options.prior_agreement &&
                        s.sigma <= options.prior_max_pair_sigma;
    }
    if (a.num_used > 0 && (!cam.prior_focal_length || options.overwrite)) {
      c.trusted = c.num_agreeing >= options.min_prior_pairs &&
                  c.num_agreeing >= options.min_prior_fraction * c.num_samples;
    }
    // A known focal (--overwrite) is only replaced by a trusted estimate.
    if (c.num_pairs >= options.min_num_pairs && c.num_pairs > 0 && (!cam.prior_focal_length || c.trusted)) {
      colmap::Camera updated = cam;
      updated.intrinsics.SetFocal(a.focal);
      updated.prior_focal_length = c.trusted;
      db->UpdateCamera(updated);
      c.new_focal = a.focal;
      c.updated = true;
    }
    changes.push_back(c);
  }
  txn.Commit();
  return changes;
}

}  // namespace madsfm
