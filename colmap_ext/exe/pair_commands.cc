#include "colmap_ext/exe/pair_commands.h"

#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "colmap_ext/exe/option_parser.h"
#include "madsfm/geometry/pose_error.h"
#include "madsfm/io/json_writer.h"
#include "madsfm/io/pair_directory.h"

namespace madsfm {
namespace {

struct EstimatorFlags {
  HybridEstimatorOptions options;
  void Add(OptionParser* parser) {
    parser->AddDefault("reproj_threshold", &options.reproj_threshold,
                       "Inlier threshold of the depth-induced reprojection error, pixels (paper: 8 indoor, 16 outdoor).");
    parser->AddDefault("epipolar_threshold", &options.epipolar_threshold,
                       "Inlier threshold of the Sampson error, pixels (paper: 2 on 640x480, 1 on larger images).");
    parser->AddDefault("sampson_weight", &options.sampson_weight, "lambda_s, weight of the Sampson term.");
    parser->AddDefault("min_iterations", &options.min_iterations, "Minimum RANSAC iterations.");
    parser->AddDefault("min_iterations_two_focal_points", &options.min_iterations_two_focal_points,
                       "Two focal lengths, point samples only (7-point): at least this many iterations.");
    parser->AddDefault("min_iterations_shared_focal_points", &options.min_iterations_shared_focal_points,
                       "Shared focal length, point samples only (6-point): at least this many iterations.");
    parser->AddDefault("max_iterations", &options.max_iterations, "Maximum RANSAC iterations.");
    parser->AddDefault("num_lo_steps", &options.num_lo_steps, "Local-optimisation rounds per new best model.");
    parser->AddDefault("confidence", &options.confidence, "Confidence of the adaptive stopping criterion.");
    parser->AddDefault("final_reprojection_weight", &options.final_reprojection_weight,
                       "Weight of the reprojection terms in a last refinement (1: the paper's joint cost only).");
    parser->AddDefault("final_cauchy_ratio", &options.final_cauchy_ratio,
                       "Cauchy loss of the last refinement, scale = this x the epipolar inliers' robust noise level "
                       "(0: least squares).");
    parser->AddDefault("epipolar_focal_max_sigma", &options.epipolar_focal_max_sigma,
                       "Focal modes: take the epipolar inliers' own focal lengths where their relative standard "
                       "deviation is at most this and they differ from the joint ones by > 3 deviations (0: never).");
    parser->AddDefault("epipolar_focal_wide_sigma", &options.epipolar_focal_wide_sigma,
                       "Shared focal: also where that deviation is at most this and they differ by > 5 "
                       "deviations (0: off).");
    parser->AddDefault("epipolar_check_ratio", &options.epipolar_check_ratio,
                       "Calibrated: a point-only run replaces the hybrid pose when it has this many times its epipolar "
                       "inliers (0: off).");
    parser->AddDefault("sampson_cheirality", &options.sampson_cheirality,
                       "Sampson data behind a camera count as outliers (1) or not (0).");
    parser->AddDefault("cheirality_min_parallax", &options.cheirality_min_parallax,
                       "... where their rays are further apart than this many times the Sampson threshold's angle.");
    parser->AddDefault("num_lo_lsq_steps", &options.num_lo_lsq_steps,
                       "Least-squares fits with a shrinking threshold per local-optimisation round.");
    parser->AddDefault("lo_max_lm_iterations", &options.lo_max_lm_iterations,
                       "Levenberg-Marquardt iterations per least-squares fit of the local optimisation.");
    parser->AddDefault("lo_max_lm_iterations_two_focal", &options.lo_max_lm_iterations_two_focal,
                       "... with two unknown focal lengths.");
    parser->AddDefault("lo_threshold_multiplier", &options.lo_threshold_multiplier,
                       "Relaxation of the squared thresholds at the start of the local optimisation.");
    parser->AddDefault("lo_first_fit_sample_size", &options.lo_first_fit_sample_size,
                       "The local optimisation's first least-squares fit uses a random subset of at most this many "
                       "of the relaxed inliers' residual terms (reprojection and Sampson, pooled; 0: all).");
    parser->AddDefault("lo_starting_iterations", &options.lo_starting_iterations,
                       "RANSAC iterations before the first local optimisation.");
    parser->AddDefault("alt_basin_lo_margin", &options.alt_basin_lo_margin,
                       "A minimal model of another basin within this fraction of the best minimal score is locally "
                       "optimised too (0: off).");
    parser->AddDefault("lo_skip_same_basin", &options.lo_skip_same_basin,
                       "A new best minimal model in the optimised best's basin that scores no better is not locally "
                       "optimised (1) or is (0).");
    parser->AddDefault("planar_twin_min_support", &options.planar_twin_min_support,
                       "Where this fraction of the epipolar inliers fit one homography, the other decomposition of it "
                       "(the planar twin) competes with the result (0: off).");
    parser->AddDefault("low_parallax_sampson_factor", &options.low_parallax_sampson_factor,
                       "Hybrid: lambda_s is multiplied by this where, after the first local optimisation, the best "
                       "model's epipolar inliers move by a median of less than --low_parallax_noise_ratio times their "
                       "noise level once a rotation is taken out (1: off).");
    parser->AddDefault("low_parallax_noise_ratio", &options.low_parallax_noise_ratio,
                       "... that ratio (noise level: 1.4826 x the inliers' median absolute Sampson error).");
    parser->AddDefault("low_parallax_final_reprojection_weight", &options.low_parallax_final_reprojection_weight,
                       "Hybrid: --final_reprojection_weight where that low-parallax switch was taken (0-1).");
    parser->AddDefault("mixed_refinement_depth_from_triangulation", &options.mixed_refinement_depth_from_triangulation,
                       "Hybrid: after that mixed last refinement, the depth corrections start from the priors' fit to "
                       "the triangulated epipolar inliers (1) or from the refinement's values (0).");
    parser->AddDefault("retry_depth_less", &options.retry_depth_less,
                       "Hybrid: search once more when the result has almost no depth inliers (1) or not (0).");
    parser->AddDefault("scale_only_fallback", &options.scale_only_fallback,
                       "Hybrid: estimate again without shifts when the priors do not determine them (1) or not (0).");
    parser->AddDefault("max_shift_ratio", &options.max_shift_ratio,
                       "Bound of |shift| in median priors of its view (0: unbounded).");
    parser->AddDefault("final_depth_fit", &options.final_depth_fit,
                       "Fit scale and shifts to the final pose by least squares of the depth inliers (1) or not (0).");
    parser->AddDefault("depth_fit_regression", &options.depth_fit_regression,
                       "Then prefer a weighted regression of triangulated depths on the priors (1) or not (0).");
    parser->AddDefault("low_parallax_depth_fit_regression", &options.low_parallax_depth_fit_regression,
                       "Hybrid: that regression also after the low-parallax switch (1) or not (0).");
    parser->AddDefault("depth_fit_regression_in_bound", &options.depth_fit_regression_in_bound,
                       "Where that regression's shift would be beyond --max_shift_ratio, fit it on the bound (1) or "
                       "drop it (0).");
    parser->AddDefault("focal_depth_from_joint", &options.focal_depth_from_joint,
                       "Focal modes: fit the depth corrections to the joint estimate's pose and focal lengths, before "
                       "the last epipolar-only refinement moves the pose (1), or to the final pose (0).");
  }
};

nlohmann::json ResultJson(const PairResult& r) {
  nlohmann::json j;
  j["pair"] = r.pair;
  j["method"] = r.method;
  j["camera_mode"] = r.camera_mode;
  j["status"] = r.success ? "ok" : "failed";
  j["num_matches"] = r.num_matches;
  j["num_matches_with_depth"] = r.num_with_depth;
  if (r.success) {
    std::vector<double> R(9);
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) R[3 * i + k] = r.model.R(i, k);
    j["R"] = R;
    j["t"] = {r.model.t.x(), r.model.t.y(), r.model.t.z()};
    j["scale"] = r.model.scale;
    j["shift0"] = r.model.shift0;
    j["shift1"] = r.model.shift1;
    j["f0"] = r.model.f0;
    j["f1"] = r.model.f1;
    j["inliers"] = {{"reproj_0to1", r.num_inliers_reproj0},
                    {"reproj_1to0", r.num_inliers_reproj1},
                    {"sampson", r.num_inliers_sampson}};
    // NaN sigmas (not fitted) are written as null, as every non-finite number.
    j["depth_observable"] = r.depth_observable;
    j["sigma_scale"] = r.sigma_scale;
    j["sigma_shift0"] = r.sigma_shift0;
    j["sigma_shift1"] = r.sigma_shift1;
    j["shifts_dropped"] = r.shifts_dropped;
    j["scale_reset"] = r.scale_reset;
    j["low_parallax_weighting"] = r.low_parallax_weighting;
    if (r.camera_mode != "calibrated") {
      j["sigma_focal0"] = r.sigma_focal0;
      j["sigma_focal1"] = r.sigma_focal1;
    }
  }
  j["iterations"] = r.iterations;
  j["runtime_ms"] = r.runtime_ms;
  if (r.rot_err_deg) j["rot_err_deg"] = *r.rot_err_deg;
  if (r.trans_err_deg) j["trans_err_deg"] = *r.trans_err_deg;
  if (r.focal_err) j["focal_err"] = *r.focal_err;
  if (!r.notes.empty()) j["notes"] = r.notes;
  return j;
}

std::vector<std::string> SplitComma(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

double Median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string Fmt(double v, int precision = 2) {
  if (!std::isfinite(v)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", precision, v);
  return buf;
}

}  // namespace

MethodSummary Summarize(const std::string& method, const std::vector<PairResult>& results, bool two_focal) {
  MethodSummary s;
  s.method = method;
  s.auc_thresholds = two_focal ? std::vector<double>{2, 5, 10, 20} : std::vector<double>{5, 10, 20};
  std::vector<double> rot, trans, focal, pose, runtime, depth_err, depth_oracle;
  int depth_good = 0, above5 = 0, observable = 0, observable_good = 0;
  for (const PairResult& r : results) {
    if (r.method != method) continue;
    ++s.runs;
    s.failures += !r.success;
    runtime.push_back(r.runtime_ms);
    if (r.depth_err && r.depth_err_oracle) {
      depth_err.push_back(*r.depth_err);
      depth_oracle.push_back(*r.depth_err_oracle);
      const bool good = *r.depth_err <= 1.25 * *r.depth_err_oracle;
      depth_good += good;
      observable += r.depth_observable;
      observable_good += r.depth_observable && good;
    }
    s.absurd_shifts += r.absurd_shift;
    if (r.rot_err_deg && r.trans_err_deg) {
      s.has_ground_truth = true;
      rot.push_back(*r.rot_err_deg);
      trans.push_back(*r.trans_err_deg);
      pose.push_back(std::max(*r.rot_err_deg, *r.trans_err_deg));
      above5 += pose.back() > 5.0;
    }
    if (r.focal_err) {
      s.has_focal = true;
      focal.push_back(*r.focal_err);
    }
  }
  s.median_rot_err = Median(rot);
  s.median_trans_err = Median(trans);
  s.median_focal_err = Median(focal);
  s.auc = pose.empty() ? std::vector<double>(s.auc_thresholds.size(), std::nan("")) : PoseAuc(pose, s.auc_thresholds);
  s.median_runtime_ms = Median(runtime);
  s.share_pose_err_above_5 = pose.empty() ? std::nan("") : static_cast<double>(above5) / pose.size();
  s.depth_measured = static_cast<int>(depth_err.size());
  s.depth_within_125 = depth_err.empty() ? std::nan("") : static_cast<double>(depth_good) / depth_err.size();
  s.depth_observable_share = depth_err.empty() ? std::nan("") : static_cast<double>(observable) / depth_err.size();
  s.depth_within_125_observable = observable == 0 ? std::nan("") : static_cast<double>(observable_good) / observable;
  s.median_depth_err = Median(depth_err);
  s.median_depth_err_oracle = Median(depth_oracle);
  double sum = 0;
  for (double t : runtime) sum += t;
  s.mean_runtime_ms = runtime.empty() ? std::nan("") : sum / runtime.size();
  return s;
}

int RunPair(int argc, char** argv) {
  std::string pair_path, camera_mode = "calibrated", method = "hybrid";
  int seed = 0;
  EstimatorFlags flags;
  OptionParser parser("pair",
                      "Estimates the relative pose, depth scale/shifts (and focal lengths) of one pair directory\n"
                      "(docs/formats.md) and prints the result as JSON, with errors against T_0to1 if present.");
  parser.AddRequired("pair_path", &pair_path, "Pair directory holding info.json.");
  parser.AddDefault("camera_mode", &camera_mode, "calibrated | shared_focal | two_focal.");
  parser.AddDefault("method", &method, "hybrid | points | depth_only | no_shift | sampson_score.");
  parser.AddDefault("seed", &seed, "Random seed.");
  flags.Add(&parser);
  if (!parser.Parse(argc, argv, 2)) return EXIT_FAILURE;
  if (parser.help_requested()) return EXIT_SUCCESS;
  try {
    const CameraMode mode = ParseCameraMode(camera_mode);
    OptionsForMethod(method, flags.options);  // validates the name
    flags.options.seed = static_cast<uint64_t>(seed);
    flags.options.Check();
    PairReadOptions read_options;
    read_options.allow_missing_depth = true;
    const PairData pair = ReadPairDirectory(pair_path, read_options);
    if (pair.p0.size() < 5) {
      throw std::runtime_error("pair directory '" + pair_path + "' has " + std::to_string(pair.p0.size()) +
                               " matches (at least 5 needed)");
    }
    const PairResult r = EvaluatePair(pair, mode, method, flags.options);
    for (const std::string& note : r.notes) std::fprintf(stderr, "madsfm pair: note: %s\n", note.c_str());
    std::cout << DumpJson(ResultJson(r), 2) << std::endl;
    return r.success ? EXIT_SUCCESS : EXIT_FAILURE;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "madsfm pair: error: %s\n", e.what());
    return EXIT_FAILURE;
  }
}

int RunBench(int argc, char** argv) {
  std::vector<std::string> pairs_paths;
  std::string camera_mode = "calibrated", methods_arg = "hybrid,points", output_path;
  int num_threads = -1, seed = 0, num_seeds = 1;
  EstimatorFlags flags;
  OptionParser parser("bench",
                      "Runs estimator methods on many pair directories and prints, per method: pairs, failures,\n"
                      "median rotation / translation / focal error, pose-error AUC and runtime.");
  parser.AddMulti("pairs_path", &pairs_paths, true,
                  "Pair directory, directory of pair directories, or pairs.txt list (several allowed).");
  parser.AddDefault("camera_mode", &camera_mode, "calibrated | shared_focal | two_focal.");
  parser.AddDefault("method", &methods_arg, "Comma-separated methods: hybrid, points, depth_only, no_shift, sampson_score.");
  parser.AddDefault("num_threads", &num_threads, "Threads over pairs (-1: all cores). Runtimes are per call.");
  parser.AddDefault("output_path", &output_path, "If set, writes per_pair.csv and summary.json into this directory.");
  parser.AddDefault("seed", &seed, "Random seed of the first run.");
  parser.AddDefault("num_seeds", &num_seeds, "Runs per pair and method, with seeds seed, seed+1, ...");
  flags.Add(&parser);
  if (!parser.Parse(argc, argv, 2)) return EXIT_FAILURE;
  if (parser.help_requested()) return EXIT_SUCCESS;
  try {
    const CameraMode mode = ParseCameraMode(camera_mode);
    const std::vector<std::string> methods = SplitComma(methods_arg);
    if (methods.empty()) throw std::invalid_argument("--method is empty");
    for (const std::string& m : methods) OptionsForMethod(m, flags.options);
    if (num_seeds < 1) throw std::invalid_argument("--num_seeds must be >= 1");
    flags.options.Check();

    std::vector<std::string> dirs;
    for (const std::string& p : pairs_paths) {
      const auto listed = ReadPairList(p);
      dirs.insert(dirs.end(), listed.begin(), listed.end());
    }
    std::vector<PairData> pairs;
    pairs.reserve(dirs.size());
    PairReadOptions read_options;
    read_options.allow_missing_depth = true;
    for (const std::string& d : dirs) pairs.push_back(ReadPairDirectory(d, read_options));

    struct Job { int pair, method, seed; };
    std::vector<Job> jobs;
    for (int pi = 0; pi < static_cast<int>(pairs.size()); ++pi)
      for (int mi = 0; mi < static_cast<int>(methods.size()); ++mi)
        for (int s = 0; s < num_seeds; ++s) jobs.push_back({pi, mi, seed + s});
    std::vector<PairResult> results(jobs.size());
    const int threads = num_threads > 0 ? num_threads : std::max(1u, std::thread::hardware_concurrency());
    std::atomic<int> next{0}, done{0};
    std::mutex progress_mutex;
    const bool tty = isatty(STDERR_FILENO);
    auto worker = [&]() {
      for (int j; (j = next++) < static_cast<int>(jobs.size());) {
        HybridEstimatorOptions o = flags.options;
        o.seed = static_cast<uint64_t>(jobs[j].seed);
        results[j] = EvaluatePair(pairs[jobs[j].pair], mode, methods[jobs[j].method], o);
        results[j].seed = jobs[j].seed;
        const int d = ++done;
        std::lock_guard<std::mutex> lock(progress_mutex);
        const int total = static_cast<int>(jobs.size());
        if (tty) {
          const int width = 30, filled = width * d / total;
          std::fprintf(stderr, "\rbench [%s%s] %d/%d runs", std::string(filled, '#').c_str(),
                       std::string(width - filled, ' ').c_str(), d, total);
          if (d == total) std::fprintf(stderr, "\n");
        } else if (d == total || d % std::max(1, total / 10) == 0) {
          std::fprintf(stderr, "bench: %d/%d runs\n", d, total);
        }
      }
    };
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t) pool.emplace_back(worker);
    for (auto& t : pool) t.join();

    const bool two_focal = mode == CameraMode::kTwoFocal;
    nlohmann::json summary_json;
    summary_json["camera_mode"] = camera_mode;
    summary_json["num_pairs"] = pairs.size();
    summary_json["num_seeds"] = num_seeds;
    summary_json["reproj_threshold"] = flags.options.reproj_threshold;
    summary_json["epipolar_threshold"] = flags.options.epipolar_threshold;
    std::cout << "camera_mode " << camera_mode << ", " << pairs.size() << " pairs x " << num_seeds << " seeds, tau_r "
              << flags.options.reproj_threshold << " px, tau_s " << flags.options.epipolar_threshold << " px\n\n";
    std::ostringstream header, rule;
    header << "| method | runs | failures | med rot (deg) | med trans (deg) |";
    rule << "|---|---|---|---|---|";
    if (mode != CameraMode::kCalibrated) { header << " med focal err |"; rule << "---|"; }
    const MethodSummary probe = Summarize(methods[0], results, two_focal);
    for (double t : probe.auc_thresholds) { header << " AUC@" << t << " |"; rule << "---|"; }
    header << " >5 deg | depth err (oracle) | depth <=1.25x | observable (<=1.25x) | absurd | med ms | mean ms |";
    rule << "---|---|---|---|---|---|---|";
    std::cout << header.str() << "\n" << rule.str() << "\n";
    for (const std::string& m : methods) {
      const MethodSummary s = Summarize(m, results, two_focal);
      std::cout << "| " << m << " | " << s.runs << " | " << s.failures << " | " << Fmt(s.median_rot_err) << " | "
                << Fmt(s.median_trans_err) << " |";
      if (mode != CameraMode::kCalibrated) std::cout << " " << Fmt(100 * s.median_focal_err) << "% |";
      for (double a : s.auc) std::cout << " " << Fmt(100 * a) << " |";
      std::cout << " " << Fmt(100 * s.share_pose_err_above_5, 1) << "% | " << Fmt(100 * s.median_depth_err)
                << "% (" << Fmt(100 * s.median_depth_err_oracle) << "%) | " << Fmt(100 * s.depth_within_125, 1)
                << "% | " << Fmt(100 * s.depth_observable_share, 1) << "% ("
                << Fmt(100 * s.depth_within_125_observable, 1) << "%) | " << s.absurd_shifts << " |";
      std::cout << " " << Fmt(s.median_runtime_ms) << " | " << Fmt(s.mean_runtime_ms) << " |\n";
      nlohmann::json mj;
      mj["runs"] = s.runs;
      mj["failures"] = s.failures;
      if (s.has_ground_truth) {
        mj["median_rot_err_deg"] = s.median_rot_err;
        mj["median_trans_err_deg"] = s.median_trans_err;
        for (size_t k = 0; k < s.auc.size(); ++k) mj["auc@" + Fmt(s.auc_thresholds[k], 0)] = s.auc[k];
      }
      if (s.has_focal) mj["median_focal_err"] = s.median_focal_err;
      if (s.has_ground_truth) mj["share_pose_err_above_5deg"] = s.share_pose_err_above_5;
      if (s.depth_measured > 0) {
        mj["depth_measured"] = s.depth_measured;
        mj["depth_within_1.25x_oracle"] = s.depth_within_125;
        mj["median_depth_err"] = s.median_depth_err;
        mj["median_depth_err_oracle"] = s.median_depth_err_oracle;
        mj["depth_observable_share"] = s.depth_observable_share;
        if (std::isfinite(s.depth_within_125_observable)) {
          mj["depth_within_1.25x_oracle_observable"] = s.depth_within_125_observable;
        }
      }
      mj["absurd_shifts"] = s.absurd_shifts;
      mj["median_runtime_ms"] = s.median_runtime_ms;
      mj["mean_runtime_ms"] = s.mean_runtime_ms;
      summary_json["methods"][m] = mj;
    }

    if (!output_path.empty()) {
      std::filesystem::create_directories(output_path);
      const std::string csv_path = (std::filesystem::path(output_path) / "per_pair.csv").string();
      std::ofstream csv(csv_path);
      if (!csv) throw std::runtime_error("cannot write '" + csv_path + "'");
      csv << "pair,method,camera_mode,status,qw,qx,qy,qz,tx,ty,tz,f0,f1,scale,shift0,shift1,num_inliers,runtime_ms,"
             "rot_err_deg,trans_err_deg,focal_err,depth_err,depth_err_oracle,depth_support,seed,depth_observable,"
             "sigma_scale,sigma_shift0,sigma_shift1,sigma_focal0,sigma_focal1,shifts_dropped,scale_reset,"
             "low_parallax_weighting\n";
      // Numbers as the shortest round-trip text (FormatDouble), as in the JSON outputs.
      auto num = [](double v) { return FormatDouble(v); };
      auto opt = [](const std::optional<double>& v) { return v ? FormatDouble(*v) : std::string(); };
      for (const PairResult& r : results) {
        const Eigen::Quaterniond q(r.model.R);
        csv << '"' << r.pair << "\"," << r.method << ',' << r.camera_mode << ',' << (r.success ? "ok" : "failed");
        if (r.success) {
          for (double v : {q.w(), q.x(), q.y(), q.z(), r.model.t.x(), r.model.t.y(), r.model.t.z(), r.model.f0,
                           r.model.f1, r.model.scale, r.model.shift0, r.model.shift1}) {
            csv << ',' << num(v);
          }
          csv << ',' << r.num_inliers_sampson;
        } else {
          csv << ",,,,,,,,,,,,,0";
        }
        csv << ',' << num(r.runtime_ms) << ',' << opt(r.rot_err_deg) << ',' << opt(r.trans_err_deg) << ','
            << opt(r.focal_err) << ',' << opt(r.depth_err) << ',' << opt(r.depth_err_oracle) << ','
            << (r.depth_support ? std::to_string(*r.depth_support) : std::string()) << ',' << r.seed << ','
            << (r.depth_observable ? 1 : 0);
        // NaN (not estimated / not computable) as an empty field, like the other optional columns.
        for (double v : {r.sigma_scale, r.sigma_shift0, r.sigma_shift1, r.sigma_focal0, r.sigma_focal1}) {
          csv << ',' << (std::isfinite(v) ? num(v) : std::string());
        }
        csv << ',' << (r.shifts_dropped ? 1 : 0) << ',' << (r.scale_reset ? 1 : 0) << ','
            << (r.low_parallax_weighting ? 1 : 0) << '\n';
      }
      const std::string json_path = (std::filesystem::path(output_path) / "summary.json").string();
      std::ofstream js(json_path);
      if (!js) throw std::runtime_error("cannot write '" + json_path + "'");
      js << DumpJson(summary_json, 2) << "\n";
      std::fprintf(stderr, "bench: wrote %s and %s\n", csv_path.c_str(), json_path.c_str());
    }
    return EXIT_SUCCESS;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "madsfm bench: error: %s\n", e.what());
    return EXIT_FAILURE;
  }
}

}  // namespace madsfm
