#include "colmap_ext/pipeline/two_view_estimator.h"

#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "colmap_ext/camera/camera_models.h"
#include "colmap_ext/database/database.h"
#include "colmap_ext/depth/keypoint_depths.h"
#include "colmap_ext/model/reconstruction.h"
#include "colmap_ext/shard/fingerprint.h"
#include "colmap_ext/shard/shard_file.h"
#include "colmap_ext/shard/shard_plan.h"
#include "madsfm/estimators/estimate_relpose.h"
#include "madsfm/estimators/hybrid_lo_msac.h"
#include "madsfm/geometry/essential_matrix.h"

namespace madsfm {
namespace {

using colmap::image_t;
using colmap::pair_t;
using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

// Per image: undistorted normalised keypoints and the depth prior at every keypoint.
struct ImageData {
  colmap::Image image;
  const colmap::Camera* camera = nullptr;
  std::vector<Eigen::Vector2d> normalized;
  std::vector<double> depth;
  bool has_depth = false;
};

struct PairJob {
  pair_t pair_id = 0;
  const ImageData* image1 = nullptr;  // smaller id = view 0
  const ImageData* image2 = nullptr;
  CameraMode mode = CameraMode::kCalibrated;
  std::vector<std::array<uint32_t, 2>> matches;
  std::optional<int> colmap_num_inliers;  // COLMAP's own verified inlier count (nullopt: no row)
  std::vector<int> colmap_inliers;        // indices into `matches` of COLMAP's verified inlier matches (sorted)
  // Results
  HybridEstimate estimate;
  bool point_fallback = false;
  bool not_verified = false;  // point-only and COLMAP found < min_num_inliers: not estimated (see EstimatePair)
  bool ok = false;
};

uint64_t SplitMix(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// The indices into `matches` of the matches that `subset` holds too (sorted; a match listed twice in `matches` gives
// both indices).
std::vector<int> MatchIndices(const std::vector<std::array<uint32_t, 2>>& matches,
                              const std::vector<std::array<uint32_t, 2>>& subset) {
  auto key = [](const std::array<uint32_t, 2>& m) { return (static_cast<uint64_t>(m[0]) << 32) | m[1]; };
  std::vector<uint64_t> keys(subset.size());
  for (size_t k = 0; k < subset.size(); ++k) keys[k] = key(subset[k]);
  std::sort(keys.begin(), keys.end());
  std::vector<int> indices;
  for (size_t i = 0; i < matches.size(); ++i) {
    if (std::binary_search(keys.begin(), keys.end(), key(matches[i]))) indices.push_back(static_cast<int>(i));
  }
  return indices;
}

CameraMode PairMode(const std::string& requested, const colmap::Camera& c1, const colmap::Camera& c2) {
  if (requested != "auto") return ParseCameraMode(requested);
  if (c1.prior_focal_length && c2.prior_focal_length) return CameraMode::kCalibrated;
  if (c1.camera_id == c2.camera_id) return CameraMode::kSharedFocal;
  return CameraMode::kTwoFocal;
}

void EstimatePair(const TwoViewEstimatorOptions& options, PairJob* job) {
  const ImageData& a = *job->image1;
  const ImageData& b = *job->image2;
  const size_t n = job->matches.size();
  RelposeProblem p;
  p.mode = job->mode;
  p.x0.resize(n);
  p.x1.resize(n);
  p.d0.resize(n);
  p.d1.resize(n);
  const colmap::CameraIntrinsics& ka = a.camera->intrinsics;
  const colmap::CameraIntrinsics& kb = b.camera->intrinsics;
  // Focal modes work on undistorted pixel coordinates centred on the principal point (the current focal only
  // scales the normalised coordinates back to pixels; it is not used as knowledge).
  const double ua = job->mode == CameraMode::kCalibrated ? 1.0 : std::sqrt(ka.FocalX() * ka.FocalY());
  const double ub = job->mode == CameraMode::kCalibrated ? 1.0 : std::sqrt(kb.FocalX() * kb.FocalY());
  for (size_t i = 0; i < n; ++i) {
    const uint32_t ia = job->matches[i][0], ib = job->matches[i][1];
    p.x0[i] = a.normalized[ia] * ua;
    p.x1[i] = b.normalized[ib] * ub;
    p.d0[i] = a.depth[ia];
    p.d1[i] = b.depth[ib];
  }
  if (job->mode == CameraMode::kCalibrated) {
    p.pixel_scale0 = std::sqrt(ka.FocalX() * ka.FocalY());
    p.pixel_scale1 = std::sqrt(kb.FocalX() * kb.FocalY());
  } else {
    const double dim = std::max({ka.width, ka.height, kb.width, kb.height});
    p.min_focal = 0.1 * dim;
    p.max_focal = 10.0 * dim;
  }
  p.IndexDepths();
  p.guided = job->colmap_inliers;  // COLMAP's verified matches guide the sampling (guided_sampling_fraction)
  HybridEstimatorOptions eo = options.estimator;
  eo.seed = SplitMix(options.estimator.seed ^ SplitMix(job->pair_id));
  const int k_depth = (job->mode == CameraMode::kCalibrated || !eo.estimate_shift) ? 3 : 4;
  if (static_cast<int>(p.with_both_depths.size()) < std::max(k_depth, 8)) {
    eo = PointOnlyOptions(eo);
    job->point_fallback = true;
    // Every point-only model is a fundamental matrix, and COLMAP's verification already searched those (and E and H)
    // at a looser threshold (4 px by default). Where it found fewer than min_num_inliers inliers, a search here almost
    // always fails too, after running to max_iterations (10,000 six-point solves on the shared-focal path, ~0.4 s a
    // pair); it can succeed only on a weak pair COLMAP's seven-point sampling missed, worth a few inliers above the
    // minimum. Such pairs keep COLMAP's row without the search. With depth priors the pair is still estimated.
    if (job->colmap_num_inliers && *job->colmap_num_inliers < options.min_num_inliers) {
      job->not_verified = true;
      return;
    }
  }
  job->estimate = EstimateHybridRelpose(p, eo);
  // A model that could not be written as a real pose (non-finite, zero translation, no focal) is a failure: the pair
  // keeps COLMAP's row and never gets a placeholder pose.
  const AffineDepthPose& m = job->estimate.model;
  const bool focal_ok = job->mode == CameraMode::kCalibrated ||
                        (std::isfinite(m.f0) && std::isfinite(m.f1) && m.f0 > 0 && m.f1 > 0);
  const bool pose_ok = m.R.allFinite() && m.t.allFinite() && m.t.norm() > 0 && focal_ok;
  job->ok = job->estimate.success && pose_ok && job->estimate.num_inliers_sampson >= options.min_num_inliers;
}

// The pair's camera with the focal the solver estimated (COLMAP main's two_view_geometries.camera1 / camera2).
colmap::Camera WithEstimatedFocal(const colmap::Camera& camera, double focal) {
  colmap::Camera estimated = camera;
  estimated.intrinsics.SetFocal(focal);
  return estimated;
}

colmap::TwoViewGeometryRow MakeGeometryRow(const PairJob& job) {
  const AffineDepthPose& m = job.estimate.model;
  colmap::TwoViewGeometryRow row;
  row.pair_id = job.pair_id;
  for (size_t i = 0; i < job.matches.size(); ++i) {
    if (job.estimate.inliers_sampson[i]) row.inlier_matches.push_back(job.matches[i]);
  }
  const Eigen::Vector3d t_unit = m.t.normalized();
  const Eigen::Matrix3d E = CrossProductMatrix(t_unit) * m.R;
  const colmap::CameraIntrinsics& ka = job.image1->camera->intrinsics;
  const colmap::CameraIntrinsics& kb = job.image2->camera->intrinsics;
  Eigen::Matrix3d K1 = Eigen::Matrix3d::Identity(), K2 = Eigen::Matrix3d::Identity();
  if (job.mode == CameraMode::kCalibrated) {
    K1(0, 0) = ka.FocalX();
    K1(1, 1) = ka.FocalY();
    K2(0, 0) = kb.FocalX();
    K2(1, 1) = kb.FocalY();
  } else {
    K1(0, 0) = K1(1, 1) = m.f0;
    K2(0, 0) = K2(1, 1) = m.f1;
  }
  K1(0, 2) = ka.PrincipalX();
  K1(1, 2) = ka.PrincipalY();
  K2(0, 2) = kb.PrincipalX();
  K2(1, 2) = kb.PrincipalY();
  Eigen::Matrix3d F = K2.inverse().transpose() * E * K1.inverse();
  F /= F.norm();
  row.F = F;
  row.E = E;  // in focal modes: E of the estimated focals, which go with it into camera1 / camera2
  if (job.mode == CameraMode::kCalibrated) {
    row.config = colmap::kCalibrated;
  } else {
    row.config = colmap::kUncalibrated;  // as COLMAP labels pairs whose focal its own solver estimated
    row.camera1 = WithEstimatedFocal(*job.image1->camera, m.f0);
    row.camera2 = WithEstimatedFocal(*job.image2->camera, m.f1);
  }
  row.qvec = colmap::RotationToQuaternion(m.R);
  row.tvec = t_unit;
  return row;
}

colmap::MadsfmPairRow MakeMadsfmRow(const PairJob& job, const std::string& fingerprint) {
  const AffineDepthPose& m = job.estimate.model;
  colmap::MadsfmPairRow row;
  row.pair_id = job.pair_id;
  row.camera_mode = static_cast<int>(job.mode);
  row.method = job.point_fallback ? 1 : 0;
  row.options_fingerprint = fingerprint;
  row.status = job.ok ? 0 : 1;
  if (job.estimate.success) {
    row.R = m.R;
    row.t = m.t;
    row.scale = m.scale;
    row.shift1 = m.shift0;
    row.shift2 = m.shift1;
    row.focal1 = m.f0;
    row.focal2 = m.f1;
    if (job.mode == CameraMode::kCalibrated) {
      row.focal1 = std::sqrt(job.image1->camera->intrinsics.FocalX() * job.image1->camera->intrinsics.FocalY());
      row.focal2 = std::sqrt(job.image2->camera->intrinsics.FocalX() * job.image2->camera->intrinsics.FocalY());
    }
    row.num_inliers_reproj1 = job.estimate.num_inliers_reproj0;
    row.num_inliers_reproj2 = job.estimate.num_inliers_reproj1;
    row.num_inliers_sampson = job.estimate.num_inliers_sampson;
    row.num_inliers = job.estimate.num_inliers_sampson;
    row.depth_observable = job.estimate.depth_observable ? 1 : 0;
    row.sigma_scale = job.estimate.sigma_scale;
    row.sigma_shift1 = job.estimate.sigma_shift0;
    row.sigma_shift2 = job.estimate.sigma_shift1;
    row.sigma_focal1 = job.estimate.sigma_focal0;
    row.sigma_focal2 = job.estimate.sigma_focal1;
    row.score = job.estimate.score;
  }
  return row;
}

bool TableExists(const colmap::Database& db, const std::string& table) {
  for (const std::string& t : db.ListTables()) {
    if (t == table) return true;
  }
  return false;
}

void CheckMatches(const colmap::Database& db, pair_t pair_id, const std::vector<std::array<uint32_t, 2>>& matches,
                  size_t n1, size_t n2) {
  for (const auto& m : matches) {
    if (m[0] >= n1 || m[1] >= n2) {
      throw std::runtime_error("database '" + db.path() + "': matches of " + db.DescribePair(pair_id) +
                               " point past the keypoints (" + std::to_string(m[0]) + ", " + std::to_string(m[1]) +
                               " vs " + std::to_string(n1) + ", " + std::to_string(n2) + " keypoints)");
    }
  }
}

void PrintProgress(int done, int total, double elapsed, bool tty) {
  if (total <= 0) return;
  const double rate = elapsed > 0 ? done / elapsed : 0.0;
  if (tty) {
    const int width = 30, filled = width * done / total;
    std::fprintf(stderr, "\rtwo_view_estimator [%s%s] %d/%d pairs, %.0f pairs/s", std::string(filled, '#').c_str(),
                 std::string(width - filled, ' ').c_str(), done, total, rate);
    if (done == total) std::fprintf(stderr, "\n");
  } else {
    std::fprintf(stderr, "two_view_estimator: %d/%d pairs, %.0f pairs/s\n", done, total, rate);
  }
}

}  // namespace

std::set<std::pair<std::string, std::string>> ReadImagePairList(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read pair list '" + path + "'");
  std::set<std::pair<std::string, std::string>> pairs;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    std::string a, b;
    if (!(ls >> a >> b)) {
      throw std::runtime_error("pair list '" + path + "' line " + std::to_string(line_no) +
                               ": expected two image names");
    }
    pairs.insert({a, b});
    pairs.insert({b, a});
  }
  return pairs;
}

std::string FileFingerprint(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read '" + path + "'");
  colmap::Fingerprinter fp;
  char buffer[1 << 16];
  while (in.read(buffer, sizeof(buffer)) || in.gcount() > 0) fp.Add(buffer, static_cast<size_t>(in.gcount()));
  return fp.Hex();
}

std::string OptionsFingerprint(const TwoViewEstimatorOptions& o) {
  std::ostringstream s;
  s.precision(17);
  const HybridEstimatorOptions& e = o.estimator;
  // The depth folder as an absolute, normalised path: "depths", "./depths/" and "/proj/depths" are the same options
  // (shard tasks and reruns are often started from other working directories).
  std::string depth = "-";
  if (!o.depth_path.empty()) {
    std::error_code ec;
    const std::filesystem::path canonical = std::filesystem::weakly_canonical(o.depth_path, ec);
    depth = ec ? o.depth_path : canonical.lexically_normal().string();
    while (depth.size() > 1 && depth.back() == '/') depth.pop_back();
  }
  // Every option that changes a result. The version changes with the estimator's results ("madsfm-24": in the focal
  // modes the depth corrections are fitted to the joint estimate before the last refinement (focal_depth_from_joint);
  // "madsfm-23": the
  // regression of triangulated depths on the priors is fitted within the shift bound where it would be beyond it
  // (depth_fit_regression_in_bound); "madsfm-22": that regression iterates its Huber reweighting until it settles
  // and is not taken after the low-parallax switch (low_parallax_depth_fit_regression); "madsfm-21": the local
  // optimisation's first fit on a random subset of at most lo_first_fit_sample_size inliers; "madsfm-20": shared-focal
  // point-only searches run at least min_iterations_shared_focal_points; "madsfm-19": two focal
  // lengths from the epipolar evidence are not taken where a view would lose more than half of its depth inliers;
  // "madsfm-18": the low-parallax mixed last refinement in the focal modes too, the depth corrections after it from
  // the triangulation fit, and the refinements stop at a relative cost decrease of 1e-7; "madsfm-17": calibrated
  // low-parallax pairs keep depth terms in the last refinement (low_parallax_final_reprojection_weight); "madsfm-16":
  // a lower Sampson weight at low parallax (low_parallax_sampson_factor); "madsfm-15": a new best
  // minimal model in the optimised best's basin is not optimised again (lo_skip_same_basin); "madsfm-14": COLMAP's
  // verified matches guide the sampling (guided_sampling_fraction); "madsfm-13": 6 LM
  // iterations per local-optimisation fit outside two focal (lo_max_lm_iterations); "madsfm-12": the planar
  // twin of the best model competes (planar_twin_min_support); "madsfm-11": a shared
  // focal the epipolar evidence rejects by 5 of its deviations up to 5% (epipolar_focal_wide_sigma); "madsfm-10":
  // the shift bound holds for every model; "madsfm-9": undetermined shifts dropped (scale_only_fallback);
  // "madsfm-8": point-only pairs that COLMAP's verification rejected are not searched, a drifting scale is reset;
  // "madsfm-7": the epipolar focal lengths under the robust loss too; "madsfm-6": the focal lengths' standard
  // deviations stored, the robust last refinement; "madsfm-5": more iterations for two-focal point-only searches;
  // "madsfm-4": the epipolar focal lengths where they are precise; "madsfm-3": other basins' minimal models
  // optimised, depth-less results searched again), so pairs done by an older madsfm are estimated again.
  s << "madsfm-24;mode=" << o.camera_mode << ";depth=" << depth
    << ";depth_type=" << o.depth_type << ";min_inliers=" << o.min_num_inliers << ";tr=" << e.reproj_threshold
    << ";ts=" << e.epipolar_threshold << ";ls=" << e.sampson_weight << ";solvers=" << static_cast<int>(e.solvers)
    << ";scoring=" << static_cast<int>(e.scoring) << ";shift=" << e.estimate_shift << ";cheir="
    << e.sampson_cheirality << "/" << e.cheirality_min_parallax << ";it=" << e.min_iterations << "/"
    << e.min_iterations_two_focal_points << "/" << e.min_iterations_shared_focal_points << "-" << e.max_iterations
    << ";conf=" << e.confidence
    << ";guided=" << e.guided_sampling_fraction << ";lo=" << e.num_lo_steps << "/" << e.num_lo_lsq_steps << "/"
    << e.lo_threshold_multiplier << "/" << e.lo_inner_sample_multiplier << "/" << e.lo_lsq_sample_size << "/"
    << e.lo_first_fit_sample_size << "/"
    << e.lo_starting_iterations << "/" << e.lo_max_lm_iterations << "/" << e.lo_max_lm_iterations_two_focal << "/"
    << e.alt_basin_lo_margin << "/" << e.lo_skip_same_basin << "/" << e.planar_twin_min_support
    << ";lowpar=" << e.low_parallax_sampson_factor << "/" << e.low_parallax_noise_ratio << "/"
    << e.low_parallax_final_reprojection_weight << "/" << e.mixed_refinement_depth_from_triangulation
    << ";final=" << e.final_refinement << "/" << e.final_max_lm_iterations << "/" << e.final_reprojection_weight
    << "/" << e.epipolar_focal_max_sigma << "/" << e.epipolar_focal_wide_sigma << "/" << e.final_cauchy_ratio
    << ";check=" << e.epipolar_check_ratio << "/" << e.retry_depth_less << "/" << e.scale_only_fallback
    << ";depth_fit=" << e.max_shift_ratio << "/" << e.final_depth_fit << "/" << e.depth_fit_regression << "/"
    << e.low_parallax_depth_fit_regression << "/" << e.depth_fit_regression_in_bound << "/"
    << e.focal_depth_from_joint << "/" << e.max_depth_sigma
    << ";seed=" << e.seed;
  return s.str();
}

namespace {

// Where a batch of results goes: the database (single process) or a shard file.
class ResultSink {
 public:
  virtual ~ResultSink() = default;
  virtual void WriteBatch(const std::vector<PairJob>& jobs, const std::string& fingerprint) = 0;
};

class DatabaseSink : public ResultSink {
 public:
  explicit DatabaseSink(colmap::Database* db) : db_(db) {}
  // A kill leaves either all of a batch or none of it.
  void WriteBatch(const std::vector<PairJob>& jobs, const std::string& fingerprint) override {
    colmap::Database::Transaction txn(db_);
    for (const PairJob& job : jobs) {
      if (job.ok) db_->WriteTwoViewGeometry(MakeGeometryRow(job));
      db_->WriteMadsfmPair(MakeMadsfmRow(job, fingerprint));
    }
    txn.Commit();
  }

 private:
  colmap::Database* db_;
};

class ShardSink : public ResultSink {
 public:
  explicit ShardSink(colmap::ShardFile* shard) : shard_(shard) {}
  void WriteBatch(const std::vector<PairJob>& jobs, const std::string& fingerprint) override {
    shard_->Begin();
    for (const PairJob& job : jobs) {
      colmap::ShardResult result;
      if (job.ok) result.geometry = MakeGeometryRow(job);
      result.madsfm = MakeMadsfmRow(job, fingerprint);
      shard_->WriteResult(result);
    }
    shard_->Commit();
  }

 private:
  colmap::ShardFile* shard_;
};

void CheckShardOptions(const TwoViewEstimatorOptions& o) {
  if (o.num_shards < 1) throw std::invalid_argument("--num_shards must be >= 1");
  if (o.shard_index < 0 || o.shard_index >= o.num_shards) {
    throw std::invalid_argument("--shard_index " + std::to_string(o.shard_index) + " is not in [0, --num_shards = " +
                                std::to_string(o.num_shards) + ")");
  }
  if (o.num_shards > 1 && o.shard_path.empty()) {
    throw std::invalid_argument("--num_shards > 1 needs --shard_path (the database is only read when sharding)");
  }
}

// Opens the shard file of a sharded run: a new one, or the one a killed task left (resume) when it was made from
// the same database, options and split. Anything else is refused, naming the file.
std::unique_ptr<colmap::ShardFile> OpenOrCreateShard(const TwoViewEstimatorOptions& o, const colmap::ShardInfo& info,
                                                     const std::vector<pair_t>& assigned) {
  if (std::filesystem::exists(o.shard_path)) {
    if (o.overwrite) {
      std::filesystem::remove(o.shard_path);
    } else {
      auto shard = colmap::ShardFile::Open(o.shard_path, /*read_only=*/false);
      const colmap::ShardInfo& old = shard->info();
      std::string why;
      if (old.database_fingerprint != info.database_fingerprint) {
        why = "another database (or the database changed)";
      } else if (old.options_fingerprint != info.options_fingerprint) {
        why = "other options (" + old.options_fingerprint + ")";
      } else if (old.split_fingerprint != info.split_fingerprint || old.shard_index != info.shard_index) {
        why = "another split (shard " + std::to_string(old.shard_index) + " of " + std::to_string(old.num_shards) + ")";
      }
      if (!why.empty()) {
        throw std::runtime_error("shard file '" + o.shard_path + "' exists and was made from " + why +
                                 "; delete it or pass --overwrite 1");
      }
      return shard;
    }
  }
  return colmap::ShardFile::Create(o.shard_path, info, assigned);
}

}  // namespace

TwoViewEstimatorSummary RunTwoViewEstimatorImpl(const TwoViewEstimatorOptions& options) {
  const auto t_start = Clock::now();
  TwoViewEstimatorSummary summary;
  options.estimator.Check();
  if (options.camera_mode != "auto") ParseCameraMode(options.camera_mode);
  const colmap::DepthType depth_type = colmap::ParseDepthType(options.depth_type);
  if (options.batch_size < 1) throw std::invalid_argument("--batch_size must be >= 1");
  CheckShardOptions(options);
  const bool sharded = !options.shard_path.empty();
  const std::string fingerprint = OptionsFingerprint(options);
  if (!options.depth_path.empty() && !std::filesystem::is_directory(options.depth_path)) {
    throw std::runtime_error("--depth_path '" + options.depth_path + "' is not a folder");
  }

  // A sharded task only reads the database: many tasks read it at once, merge_shards writes.
  auto db = colmap::Database::Open(options.database_path, /*read_only=*/sharded);
  const std::vector<colmap::Camera> cameras = db->ReadCameras();
  std::map<colmap::camera_t, const colmap::Camera*> camera_by_id;
  for (const auto& c : cameras) camera_by_id[c.camera_id] = &c;
  std::map<image_t, ImageData> images;
  for (const colmap::Image& im : db->ReadImages()) images[im.image_id].image = im;

  // Pairs to estimate.
  std::vector<std::pair<pair_t, int>> pairs = db->ReadMatchedPairs();
  if (!options.pair_list.empty()) {
    const auto allowed = ReadImagePairList(options.pair_list);
    std::vector<std::pair<pair_t, int>> kept;
    for (const auto& pr : pairs) {
      image_t i1, i2;
      colmap::PairIdToImagePair(pr.first, &i1, &i2);
      if (images.count(i1) && images.count(i2) && allowed.count({images[i1].image.name, images[i2].image.name})) {
        kept.push_back(pr);
      }
    }
    pairs = kept;
  }
  summary.num_pairs = static_cast<int>(pairs.size());
  colmap::PairCounts candidates;
  for (const auto& pr : pairs) {
    if (pr.second < options.min_num_matches) ++summary.num_skipped_few_matches;
    else candidates.push_back(pr);
  }

  // Sharded: this task's part of the split, and its shard file (resumed when a killed task left one).
  std::unique_ptr<colmap::ShardFile> shard;
  std::set<pair_t> done_in_shard;
  if (sharded) {
    const auto split = colmap::SplitPairsIntoShards(candidates, options.num_shards);
    const std::vector<pair_t>& mine = split[options.shard_index];
    colmap::ShardInfo info;
    info.database_path = options.database_path;
    info.database_fingerprint = colmap::DatabaseFingerprint(*db);
    info.options_fingerprint = fingerprint;
    info.split_fingerprint = colmap::SplitFingerprint(candidates, options.num_shards);
    info.num_shards = options.num_shards;
    info.shard_index = options.shard_index;
    info.num_split_pairs = static_cast<long long>(candidates.size());
    info.min_num_matches = options.min_num_matches;
    if (!options.pair_list.empty()) {
      info.pair_list_path = std::filesystem::absolute(options.pair_list).string();
      info.pair_list_fingerprint = FileFingerprint(options.pair_list);
    }
    info.madsfm_version = MADSFM_VERSION;
    shard = OpenOrCreateShard(options, info, mine);
    for (pair_t p : shard->ResultPairs()) done_in_shard.insert(p);
    const std::set<pair_t> mine_set(mine.begin(), mine.end());
    colmap::PairCounts kept;
    for (const auto& pr : candidates) {
      if (mine_set.count(pr.first)) kept.push_back(pr);
    }
    candidates = kept;
    summary.num_shard_pairs = static_cast<int>(candidates.size());
  }

  // Which pairs still need work (resume), and which images they touch.
  std::vector<pair_t> todo;
  std::set<image_t> needed;
  // Nothing is written before every input has been read and checked: a rejected run leaves the database
  // exactly as it was (docs/robustness.md).
  const bool have_results = TableExists(*db, "madsfm_two_view_geometries");
  for (const auto& [pair_id, num_matches] : candidates) {
    if (!options.overwrite && have_results) {
      const auto done = db->ReadMadsfmPair(pair_id);
      if (done && done->options_fingerprint == fingerprint) {
        ++summary.num_skipped_done;
        continue;
      }
    }
    if (done_in_shard.count(pair_id)) {
      ++summary.num_skipped_done;
      continue;
    }
    image_t i1, i2;
    colmap::PairIdToImagePair(pair_id, &i1, &i2);
    if (!images.count(i1) || !images.count(i2)) {
      throw std::runtime_error("database '" + options.database_path + "': " + db->DescribePair(pair_id) +
                               " has matches, but image_id " + std::to_string(images.count(i1) ? i2 : i1) +
                               " is not in the images table");
    }
    todo.push_back(pair_id);
    needed.insert(i1);
    needed.insert(i2);
  }

  // Read and prepare every needed image once: cameras, undistorted keypoints, depth at the keypoints.
  const auto t_read = Clock::now();
  for (image_t id : needed) {
    ImageData& data = images[id];
    const auto cam = camera_by_id.find(data.image.camera_id);
    if (cam == camera_by_id.end()) {
      throw std::runtime_error("database '" + options.database_path + "': " + db->DescribeImage(id) +
                               " uses camera_id " + std::to_string(data.image.camera_id) +
                               ", which is not in the cameras table");
    }
    data.camera = cam->second;
    const colmap::CameraIntrinsics& k = data.camera->intrinsics;
    if (!colmap::IsSupportedCameraModel(k.model_id)) {
      throw std::runtime_error("database '" + options.database_path + "': " +
                               db->DescribeCamera(data.camera->camera_id) + " has model " +
                               colmap::CameraModelName(k.model_id) +
                               ", which madsfm does not support (supported: SIMPLE_PINHOLE, PINHOLE, SIMPLE_RADIAL, "
                               "RADIAL, OPENCV, FULL_OPENCV, OPENCV_FISHEYE)");
    }
    const std::vector<Eigen::Vector2d> keypoints = db->ReadKeypoints(id);
    data.normalized.resize(keypoints.size());
    for (size_t i = 0; i < keypoints.size(); ++i) data.normalized[i] = colmap::ImageToCamera(k, keypoints[i]);
    if (!options.depth_path.empty()) {
      colmap::KeypointDepths kd =
          colmap::LoadKeypointDepths(options.depth_path, data.image.name, k.width, k.height, keypoints, depth_type);
      data.depth = std::move(kd.depth);
      data.has_depth = !kd.sidecar.empty();
    } else {
      data.depth.assign(keypoints.size(), std::numeric_limits<double>::quiet_NaN());
    }
    summary.num_images_with_depth += data.has_depth;
  }
  summary.num_images = static_cast<int>(needed.size());
  summary.read_seconds += Seconds(t_read, Clock::now());

  // Check every pair's match indices against the keypoints before the first write.
  const auto t_check = Clock::now();
  for (pair_t pair_id : todo) {
    image_t i1, i2;
    colmap::PairIdToImagePair(pair_id, &i1, &i2);
    CheckMatches(*db, pair_id, db->ReadMatches(pair_id), images[i1].normalized.size(), images[i2].normalized.size());
  }
  summary.read_seconds += Seconds(t_check, Clock::now());

  std::unique_ptr<ResultSink> sink;
  if (sharded) {
    sink = std::make_unique<ShardSink>(shard.get());
  } else {
    if (!todo.empty()) {
      colmap::Database::Transaction txn(db.get());
      db->CreateMadsfmTables();
      db->BackupTwoViewGeometries();
      txn.Commit();
    }
    sink = std::make_unique<DatabaseSink>(db.get());
  }

  const int threads = options.num_threads > 0 ? options.num_threads
                                              : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const bool tty = options.progress && isatty(STDERR_FILENO);
  int done = 0;
  const auto t_loop = Clock::now();
  auto last_progress = t_loop;
  for (size_t start = 0; start < todo.size(); start += options.batch_size) {
    const size_t end = std::min(todo.size(), start + options.batch_size);
    std::vector<PairJob> jobs(end - start);
    // Read the batch's matches (one connection, this thread).
    const auto t0 = Clock::now();
    for (size_t j = 0; j < jobs.size(); ++j) {
      PairJob& job = jobs[j];
      job.pair_id = todo[start + j];
      image_t i1, i2;
      colmap::PairIdToImagePair(job.pair_id, &i1, &i2);
      job.image1 = &images[i1];
      job.image2 = &images[i2];
      job.mode = PairMode(options.camera_mode, *job.image1->camera, *job.image2->camera);
      job.matches = db->ReadMatches(job.pair_id);
      const auto colmap_inliers = db->ReadColmapInlierMatches(job.pair_id);
      if (colmap_inliers) {
        job.colmap_num_inliers = static_cast<int>(colmap_inliers->size());
        job.colmap_inliers = MatchIndices(job.matches, *colmap_inliers);
      }
    }
    const auto t1 = Clock::now();
    summary.read_seconds += Seconds(t0, t1);
    // Estimate in parallel.
    std::atomic<size_t> next{0};
    auto worker = [&]() {
      for (size_t j; (j = next++) < jobs.size();) EstimatePair(options, &jobs[j]);
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
    worker();
    for (auto& t : pool) t.join();
    const auto t2 = Clock::now();
    summary.estimate_seconds += Seconds(t1, t2);
    // Write the batch in one transaction (database or shard file).
    sink->WriteBatch(jobs, fingerprint);
    for (const PairJob& job : jobs) {
      summary.estimate_cpu_seconds += job.estimate.runtime_ms / 1000.0;
      summary.num_iterations += job.estimate.iterations;
      if (job.ok) {
        ++summary.num_estimated;
        summary.num_point_fallback += job.point_fallback;
      } else if (job.not_verified) {
        ++summary.num_not_verified;
      } else {
        ++summary.num_failed;
      }
    }
    summary.write_seconds += Seconds(t2, Clock::now());
    done += static_cast<int>(jobs.size());
    if (options.on_batch_written) options.on_batch_written(done, static_cast<int>(todo.size()));
    if (options.progress && (Seconds(last_progress, Clock::now()) > 1.0 || done == static_cast<int>(todo.size()))) {
      PrintProgress(done, static_cast<int>(todo.size()), Seconds(t_loop, Clock::now()), tty);
      last_progress = Clock::now();
    }
  }
  summary.total_seconds = Seconds(t_start, Clock::now());
  return summary;
}

}  // namespace madsfm
