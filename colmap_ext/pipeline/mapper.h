// The whole madsfm pipeline on a COLMAP project (`madsfm mapper`, colmap_ext/exe/mapper_command.h):
// two_view_estimator, focal_estimator, seed_model, then COLMAP's incremental mapper, with fallbacks so that the
// result is never worse than plain `colmap mapper` in registered images:
//
//  1. seeded:           colmap mapper --input_path OUT/seed (when a pair passed seed_model's checks), repeated
//                       with the focal fixed when bundle adjustment drifted on a low-parallax seed or cannot
//                       determine the focal as well as the pairs did (seeded_fixed_focal, see
//                       fix_focal_low_parallax, fix_focal_ba_uncertain and DecideFocalFix);
//  2. unseeded:         colmap mapper on madsfm's two-view geometries, COLMAP choosing the initial pair;
//  3. unseeded_relaxed: the same with relaxed initial-pair constraints (--Mapper.init_min_tri_angle, ...), only
//                       when attempt 2 produced no model;
//  4. colmap_rows:      colmap mapper on a copy of the database with COLMAP's own rows put back (`madsfm restore`
//                       on the copy: COLMAP's two-view geometries and cameras), i.e. plain COLMAP.
// Attempts run in this order until one registers every image that has a verified pair (the "expected" count);
// the model with the most registered images is kept (the earlier attempt on ties) and copied to OUT/0.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "colmap_ext/model/focal_uncertainty.h"
#include "colmap_ext/pipeline/focal_estimator.h"
#include "colmap_ext/pipeline/seed_model.h"
#include "colmap_ext/pipeline/two_view_estimator.h"

namespace madsfm {

struct MapperOptions {
  TwoViewEstimatorOptions two_view;  // database_path, depth_path, camera_mode, thresholds, threads
  FocalEstimatorOptions focal;       // database_path is set from two_view
  SeedModelOptions seed;             // database_path and output_path are set by RunMapperImpl
  std::string image_path;
  std::string output_path;           // seed/, <attempt>/, 0/ (the kept model), colmap_mapper_<attempt>.log
  std::string colmap_path = "colmap";
  // Passed to every colmap mapper run unchanged ("--Mapper.xxx", "value", ...).
  std::vector<std::string> colmap_mapper_args;
  // Attempt 3: these replace COLMAP's defaults (16 deg, 100) unless given in colmap_mapper_args; COLMAP halves
  // them once more itself when no initial pair is found.
  double relaxed_init_min_tri_angle = 4.0;
  int relaxed_init_min_num_inliers = 50;
  bool fallback = true;              // false: only the seeded run (or unseeded when there is no seed)
  // Low parallax (a depth-backed seed) with one camera shared by all images whose focal focal_estimator trusts:
  // when the seeded run's bundle adjustment moves that focal by more than the estimate's uncertainty (3 robust sigmas
  // of the pairs' estimates over sqrt(pairs), at least 1%), the seeded run is
  // repeated with the focal fixed (--Mapper.ba_refine_focal_length 0; attempt "seeded_fixed_focal"), unless
  // colmap_mapper_args set that option. At 1-2 deg of parallax bundle adjustment cannot tell a shared focal length
  // from depth and can drift far from the depth-backed value.
  bool fix_focal_low_parallax = true;
  // The same rerun, with any seed, when bundle adjustment determines that focal less well than focal_estimator's
  // pairs (colmap::BundleFocalUncertainty of the seeded model against 1.4826 x the pairs' robust spread over
  // sqrt(pairs)) and moved it by more than that: forward motion leaves the focal unobservable to the epipolar
  // geometry, and bundle adjustment's value is noise.
  bool fix_focal_ba_uncertain = true;
};

struct MapperAttempt {
  std::string name;        // seeded, unseeded, unseeded_relaxed, colmap_rows
  std::string model_path;  // the largest model it wrote ("" if none)
  std::string log_path;
  int exit_code = 0;
  int num_registered = 0;
  size_t num_points3D = 0;
  double seconds = 0;
};

struct MapperSummary {
  TwoViewEstimatorSummary two_view;
  double two_view_seconds = 0;
  std::vector<FocalChange> focal;
  double focal_seconds = 0;
  bool seeded = false;
  SeedModelSummary seed;
  std::string seed_failure;  // why no seed was written (seeded == false)
  double seed_seconds = 0;
  double focal_drift = 0;    // |f after the seeded run's bundle adjustment / f of focal_estimator - 1| (one camera)
  double focal_ba_sigma = 0;  // relative standard deviation of that focal in the seeded model's bundle adjustment
  bool focal_fixed = false;  // the fixed-focal rerun was made and kept (fix_focal_low_parallax / _ba_uncertain)
  int num_expected = 0;      // images with at least one verified pair of >= Mapper.min_num_matches inliers
  std::vector<MapperAttempt> attempts;
  int kept = -1;             // index into attempts of the model in final_path
  std::string final_path;    // OUT/0
  size_t num_points3D = 0;
  double mean_reproj_error = 0;
  double total_seconds = 0;
};

// Progress lines (one per finished step / attempt) go to report(false, line), warnings (no seed, a failed or short
// colmap run, which model is kept) to report(true, line), when set. Throws std::runtime_error /
// std::invalid_argument naming the file or option on bad input, and when no attempt produced a model (naming every
// colmap mapper log).
MapperSummary RunMapperImpl(const MapperOptions& options,
                            const std::function<void(bool warning, const std::string& line)>& report = {});

// Whether the seeded run is repeated with the trusted focal `estimate` fixed, given the focal bundle adjustment
// ended at and, when known, its standard deviation there (see MapperOptions::fix_focal_low_parallax, applied when
// low_parallax_rule, and fix_focal_ba_uncertain, applied when ba_uncertain_rule). drift: |focal_after_ba /
// estimate.new_focal - 1|; reason: the progress line when fix.
struct FocalFixDecision {
  bool fix = false;
  double drift = 0.0;
  std::string reason;
};
FocalFixDecision DecideFocalFix(const FocalChange& estimate, double focal_after_ba,
                                const std::optional<colmap::FocalUncertainty>& ba, bool low_parallax_rule,
                                bool ba_uncertain_rule);

// Resolves a program name against PATH (or checks an explicit path). Empty if not found.
std::string FindExecutable(const std::string& name);

}  // namespace madsfm
