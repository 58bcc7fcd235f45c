#include "colmap_ext/exe/mapper_command.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "colmap_ext/pipeline/focal_estimator.h"
#include "colmap_ext/exe/option_parser.h"
#include "colmap_ext/pipeline/seed_model.h"
#include "colmap_ext/pipeline/two_view_estimator.h"
#include "colmap_ext/model/reconstruction.h"

extern char** environ;

namespace madsfm {
namespace {

using Clock = std::chrono::steady_clock;
double Seconds(Clock::time_point a) { return std::chrono::duration<double>(Clock::now() - a).count(); }

// Resolves a program name against PATH (or checks an explicit path). Empty if not found.
std::string FindExecutable(const std::string& name) {
  if (name.find('/') != std::string::npos) return access(name.c_str(), X_OK) == 0 ? name : "";
  const char* path = std::getenv("PATH");
  std::stringstream ss(path ? path : "");
  std::string dir;
  while (std::getline(ss, dir, ':')) {
    const std::string candidate = (dir.empty() ? "." : dir) + "/" + name;
    if (access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return "";
}

// Runs argv with stdout and stderr appended to log_path; returns the exit status (-1 if it could not start).
int RunLogged(const std::vector<std::string>& args, const std::string& log_path) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid;
  const int rc = posix_spawn(&pid, args[0].c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) return -1;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return -1;
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

std::string Tail(const std::string& path, int lines) {
  std::ifstream in(path);
  std::vector<std::string> all;
  for (std::string l; std::getline(in, l);) all.push_back(l);
  std::string out;
  for (size_t i = all.size() > static_cast<size_t>(lines) ? all.size() - lines : 0; i < all.size(); ++i)
    out += all[i] + "\n";
  return out;
}

}  // namespace

int RunMapper(int argc, char** argv) {
  TwoViewEstimatorOptions tv;
  std::string image_path, output_path, colmap_path = "colmap";
  double min_tri_angle = 4.0;
  // Everything of the form --Mapper.xxx value is passed to colmap mapper unchanged.
  std::vector<std::string> passthrough;
  std::vector<char*> own_args = {argv[0], argv[1]};
  for (int i = 2; i < argc; ++i) {
    if (std::strncmp(argv[i], "--Mapper.", 9) == 0) {
      passthrough.push_back(argv[i]);
      if (std::strchr(argv[i], '=') == nullptr && i + 1 < argc) passthrough.push_back(argv[++i]);
    } else {
      own_args.push_back(argv[i]);
    }
  }
  OptionParser parser(
      "mapper",
      "The whole madsfm pipeline on a COLMAP project: two_view_estimator (hybrid affine-depth estimation of every\n"
      "matched pair), focal_estimator (per-camera focal lengths), seed_model (initial pair + two-view model), then\n"
      "`colmap mapper --input_path <output_path>/seed --output_path <output_path>/0`. Options --Mapper.* are passed\n"
      "to colmap mapper. Run COLMAP's feature_extractor and a matcher first.");
  parser.AddRequired("database_path", &tv.database_path, "COLMAP database with keypoints and matches.");
  parser.AddRequired("image_path", &image_path, "Image folder (for colmap mapper).");
  parser.AddRequired("output_path", &output_path, "Output folder: seed/, 0/ (final model), logs.");
  parser.AddDefault("depth_path", &tv.depth_path, "Folder of depth sidecars (docs/formats.md).");
  parser.AddDefault("depth_type", &tv.depth_type, "depth | disparity.");
  parser.AddDefault("camera_mode", &tv.camera_mode, "auto | calibrated | shared_focal | two_focal.");
  parser.AddDefault("num_threads", &tv.num_threads, "Threads (-1: all cores).");
  parser.AddDefault("reproj_threshold", &tv.estimator.reproj_threshold, "Reprojection inlier threshold, px.");
  parser.AddDefault("epipolar_threshold", &tv.estimator.epipolar_threshold, "Sampson inlier threshold, px.");
  parser.AddDefault("min_tri_angle", &min_tri_angle, "Minimum median triangulation angle of the initial pair, deg.");
  parser.AddDefault("colmap_path", &colmap_path, "The colmap executable.");
  if (!parser.Parse(static_cast<int>(own_args.size()), own_args.data(), 2)) return EXIT_FAILURE;
  if (parser.help_requested()) return EXIT_SUCCESS;
  try {
    const std::string colmap = FindExecutable(colmap_path);
    if (colmap.empty()) {
      throw std::runtime_error("colmap executable '" + colmap_path +
                               "' not found (install Debian's colmap package or pass --colmap_path)");
    }
    if (!std::filesystem::is_directory(image_path)) throw std::runtime_error("--image_path '" + image_path + "' is not a folder");
    std::filesystem::create_directories(output_path);
    const auto t0 = Clock::now();
    const TwoViewEstimatorSummary tvs = RunTwoViewEstimatorImpl(tv);
    const double t_two_view = Seconds(t0);
    std::printf("[1/4] two_view_estimator: %d pairs estimated (%d point-only), %d failed, %d already done (%.1f s)\n",
                tvs.num_estimated, tvs.num_point_fallback, tvs.num_failed, tvs.num_skipped_done, t_two_view);

    const auto t1 = Clock::now();
    FocalEstimatorOptions fo;
    fo.database_path = tv.database_path;
    const auto changes = RunFocalEstimatorImpl(fo);
    int updated = 0;
    for (const auto& c : changes) {
      if (!c.updated) continue;
      ++updated;
      std::printf("      camera %u: focal %.1f -> %.1f px (%d pairs, spread %.2f%%)\n", c.camera_id, c.old_focal,
                  c.new_focal, c.num_pairs, 100 * c.spread);
    }
    std::printf("[2/4] focal_estimator: %d of %zu cameras updated (%.1f s)\n", updated, changes.size(), Seconds(t1));

    const auto t2 = Clock::now();
    SeedModelOptions so;
    so.database_path = tv.database_path;
    so.output_path = (std::filesystem::path(output_path) / "seed").string();
    so.min_tri_angle_deg = min_tri_angle;
    const SeedModelSummary ss = RunSeedModelImpl(so);
    std::printf("[3/4] seed_model: initial pair '%s' - '%s', %d inliers, %.1f deg, %d points (%.1f s)\n",
                ss.name1.c_str(), ss.name2.c_str(), ss.num_inliers, ss.median_tri_angle_deg, ss.num_points3D,
                Seconds(t2));

    const auto t3 = Clock::now();
    const std::string final_path = (std::filesystem::path(output_path) / "0").string();
    std::filesystem::create_directories(final_path);
    const std::string log = (std::filesystem::path(output_path) / "colmap_mapper.log").string();
    std::vector<std::string> args = {colmap, "mapper", "--database_path", tv.database_path, "--image_path",
                                     image_path, "--input_path", so.output_path, "--output_path", final_path};
    args.insert(args.end(), passthrough.begin(), passthrough.end());
    const int rc = RunLogged(args, log);
    if (rc != 0) {
      throw std::runtime_error("colmap mapper failed (exit " + std::to_string(rc) + "); last lines of " + log + ":\n" +
                               Tail(log, 15));
    }
    const colmap::Reconstruction model = colmap::ReadReconstruction(final_path);
    double err = 0;
    for (const auto& [id, p] : model.points3D) err += p.error;
    std::printf("[4/4] colmap mapper: %zu images registered, %zu points, mean reprojection error %.3f px (%.1f s)\n",
                model.images.size(), model.points3D.size(), model.points3D.empty() ? 0.0 : err / model.points3D.size(),
                Seconds(t3));
    std::printf("mapper: model in %s (total %.1f s)\n", final_path.c_str(), Seconds(t0));
    return EXIT_SUCCESS;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "madsfm mapper: error: %s\n", e.what());
    return EXIT_FAILURE;
  }
}

}  // namespace madsfm
