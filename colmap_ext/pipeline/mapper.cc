#include "colmap_ext/pipeline/mapper.h"

#include <fcntl.h>
#include <spawn.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include "colmap_ext/database/database.h"
#include "colmap_ext/io/file_copy.h"
#include "colmap_ext/model/focal_uncertainty.h"
#include "colmap_ext/model/reconstruction.h"

extern char** environ;

namespace madsfm {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
double Seconds(Clock::time_point a) { return std::chrono::duration<double>(Clock::now() - a).count(); }

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

// The value of option `name` ("--Mapper.xxx") in args given as "--name value" or "--name=value"; "" if absent.
bool FindArg(const std::vector<std::string>& args, const std::string& name, std::string* value) {
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] == name) {
      *value = i + 1 < args.size() ? args[i + 1] : "";
      return true;
    }
    if (args[i].rfind(name + "=", 0) == 0) {
      *value = args[i].substr(name.size() + 1);
      return true;
    }
  }
  return false;
}

// Images that have at least one two_view_geometries row with >= min_num_matches inlier matches: what the
// incremental mapper can register at best.
int CountConnectedImages(const std::string& database_path, int min_num_matches) {
  auto db = colmap::Database::Open(database_path, /*read_only=*/true);
  sqlite3_stmt* st = nullptr;
  if (sqlite3_prepare_v2(db->handle(), "SELECT pair_id FROM two_view_geometries WHERE rows >= ?", -1, &st, nullptr) !=
      SQLITE_OK) {
    throw std::runtime_error("database '" + database_path + "': " + sqlite3_errmsg(db->handle()));
  }
  sqlite3_bind_int(st, 1, min_num_matches);
  std::set<colmap::image_t> images;
  while (sqlite3_step(st) == SQLITE_ROW) {
    colmap::image_t i1, i2;
    colmap::PairIdToImagePair(static_cast<colmap::pair_t>(sqlite3_column_int64(st, 0)), &i1, &i2);
    images.insert(i1);
    images.insert(i2);
  }
  sqlite3_finalize(st);
  return static_cast<int>(images.size());
}

// A copy of the database (consistent, via VACUUM INTO) with COLMAP's original rows put back.
void WriteColmapRowsCopy(const std::string& database_path, const std::string& copy_path) {
  fs::remove(copy_path);
  {
    auto db = colmap::Database::Open(database_path, /*read_only=*/true);
    std::string quoted;
    for (char c : copy_path) quoted += c == '\'' ? std::string("''") : std::string(1, c);
    char* err = nullptr;
    if (sqlite3_exec(db->handle(), ("VACUUM INTO '" + quoted + "'").c_str(), nullptr, nullptr, &err) != SQLITE_OK) {
      const std::string msg = err ? err : "unknown error";
      sqlite3_free(err);
      throw std::runtime_error("cannot copy database '" + database_path + "' to '" + copy_path + "': " + msg);
    }
  }
  auto copy = colmap::Database::Open(copy_path);
  copy->RestoreTwoViewGeometries();
}

bool HasModel(const fs::path& dir) {
  return fs::exists(dir / "images.bin") || fs::exists(dir / "images.txt");
}

// The model with the most registered images in dir itself or its subfolders 0/, 1/, ... ("" if none).
std::string LargestModel(const fs::path& dir, int* num_registered, size_t* num_points3D) {
  std::vector<fs::path> candidates;
  if (HasModel(dir)) candidates.push_back(dir);
  if (fs::is_directory(dir)) {
    for (const auto& e : fs::directory_iterator(dir)) {
      if (e.is_directory() && HasModel(e.path())) candidates.push_back(e.path());
    }
  }
  std::sort(candidates.begin(), candidates.end());
  std::string best;
  *num_registered = 0;
  *num_points3D = 0;
  for (const fs::path& c : candidates) {
    try {
      const colmap::Reconstruction model = colmap::ReadReconstruction(c.string());
      if (best.empty() || static_cast<int>(model.images.size()) > *num_registered) {
        best = c.string();
        *num_registered = static_cast<int>(model.images.size());
        *num_points3D = model.points3D.size();
      }
    } catch (const std::exception&) {
      // A model colmap left half-written: not a candidate.
    }
  }
  return best;
}

void CopyModel(const std::string& from, const std::string& to) {
  fs::create_directories(to);
  for (const char* f : {"cameras", "images", "points3D"}) {
    for (const char* ext : {".bin", ".txt"}) {
      const fs::path src = fs::path(from) / (std::string(f) + ext), dst = fs::path(to) / (std::string(f) + ext);
      if (fs::exists(src)) {
        colmap::CopyFileContents(src, dst);
      } else {
        fs::remove(dst);  // a stale file of the other format would be read instead
      }
    }
  }
}

}  // namespace

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

FocalFixDecision DecideFocalFix(const FocalChange& estimate, double focal_after_ba,
                                const std::optional<colmap::FocalUncertainty>& ba, bool low_parallax_rule,
                                bool ba_uncertain_rule) {
  FocalFixDecision d;
  d.drift = std::abs(focal_after_ba / estimate.new_focal - 1.0);
  const double root_n = std::sqrt(std::max(1, estimate.num_pairs));
  char buf[320];
  // (a) Low parallax: beyond 3 robust sigmas of the pairs' log focal over sqrt(pairs), at least 1%.
  const double allowed = std::max(0.01, 3.0 * estimate.spread / root_n);
  if (low_parallax_rule && d.drift > allowed) {
    std::snprintf(buf, sizeof(buf),
                  "      low parallax: bundle adjustment moved the focal from %.1f to %.1f px (%.1f%%, beyond the %.1f%% "
                  "its %d depth-backed pairs support; its own sigma %.2f%%); running again with the focal fixed",
                  estimate.new_focal, focal_after_ba, 100 * d.drift, 100 * allowed, estimate.num_pairs,
                  ba ? 100 * ba->Relative() : -1.0);
    d.fix = true;
    d.reason = buf;
    return d;
  }
  // (b) Bundle adjustment determines the focal less well than the pairs (1.4826 x the MAD is the normal sigma) and
  // moved it by more than the pairs' sigma.
  const double sigma_pairs = 1.4826 * estimate.spread / root_n;
  if (ba_uncertain_rule && ba && ba->Relative() > sigma_pairs && d.drift > sigma_pairs) {
    std::snprintf(buf, sizeof(buf),
                  "      bundle adjustment determines the focal to +-%.2f%% (1 sigma), its %d depth-backed pairs to "
                  "+-%.2f%%, and it moved it from %.1f to %.1f px (%.2f%%); running again with the focal fixed",
                  100 * ba->Relative(), estimate.num_pairs, 100 * sigma_pairs, estimate.new_focal, focal_after_ba,
                  100 * d.drift);
    d.fix = true;
    d.reason = buf;
  }
  return d;
}

MapperSummary RunMapperImpl(const MapperOptions& options, const std::function<void(bool, const std::string&)>& report) {
  auto say = [&](bool warning, const std::string& line) {
    if (report) report(warning, line);
  };
  char buf[512];
  const std::string colmap = FindExecutable(options.colmap_path);
  if (colmap.empty()) {
    throw std::runtime_error("--colmap_path: colmap executable '" + options.colmap_path +
                             "' not found (install Debian's colmap package or pass --colmap_path)");
  }
  if (!fs::is_directory(options.image_path)) {
    throw std::runtime_error("--image_path '" + options.image_path + "' is not a folder");
  }
  for (size_t i = 0; i < options.colmap_mapper_args.size(); ++i) {
    const std::string& a = options.colmap_mapper_args[i];
    if (a.rfind("--Mapper.", 0) == 0 && a.find('=') == std::string::npos &&
        (i + 1 >= options.colmap_mapper_args.size() || options.colmap_mapper_args[i + 1].rfind("--", 0) == 0)) {
      throw std::invalid_argument("option '" + a + "' (passed to colmap mapper) needs a value");
    }
    if (a.rfind("--Mapper.", 0) == 0 && a.find('=') == std::string::npos) ++i;
  }
  const fs::path out(options.output_path);
  MapperSummary s;
  const auto t0 = Clock::now();

  s.two_view = RunTwoViewEstimatorImpl(options.two_view);
  s.two_view_seconds = Seconds(t0);
  fs::create_directories(out);  // after the database and depth checks: bad input leaves no output folder
  std::snprintf(buf, sizeof(buf),
                "[1/4] two_view_estimator: %d pairs estimated (%d point-only), %d failed, %d point-only not estimated "
                "(COLMAP's verification found too few inliers), %d already done (%.1f s)",
                s.two_view.num_estimated, s.two_view.num_point_fallback, s.two_view.num_failed,
                s.two_view.num_not_verified, s.two_view.num_skipped_done, s.two_view_seconds);
  say(false, buf);

  const auto t1 = Clock::now();
  FocalEstimatorOptions fo = options.focal;
  fo.database_path = options.two_view.database_path;
  s.focal = RunFocalEstimatorImpl(fo);
  s.focal_seconds = Seconds(t1);
  int updated = 0;
  for (const FocalChange& c : s.focal) {
    if (c.updated) ++updated;
    if (c.updated) {
      std::snprintf(buf, sizeof(buf),
                    "      camera %u: focal %.1f -> %.1f px (%d of %d depth-backed pairs within %.0f%%, sigma <= "
                    "%.2f%%)%s",
                    c.camera_id, c.old_focal, c.new_focal, c.num_agreeing, c.num_samples, 100 * fo.prior_agreement,
                    100 * fo.prior_max_pair_sigma,
                    c.trusted ? ": prior" : ": initial value only (prior_focal_length = 0)");
      say(false, buf);
    } else if (!c.had_prior && c.num_samples == 0) {
      std::snprintf(buf, sizeof(buf), "      camera %u: no depth-backed pair estimates, COLMAP's focal %.1f px kept",
                    c.camera_id, c.old_focal);
      say(false, buf);
    }
  }
  std::snprintf(buf, sizeof(buf), "[2/4] focal_estimator: %d of %zu cameras updated (%.1f s)", updated,
                s.focal.size(), s.focal_seconds);
  say(false, buf);

  const auto t2 = Clock::now();
  SeedModelOptions so = options.seed;
  so.database_path = options.two_view.database_path;
  so.depth_path = options.two_view.depth_path;
  so.depth_type = options.two_view.depth_type;
  so.output_path = (out / "seed").string();
  try {
    s.seed = RunSeedModelImpl(so);
    s.seeded = true;
    s.seed_seconds = Seconds(t2);
    std::snprintf(buf, sizeof(buf),
                  "[3/4] seed_model: initial pair '%s' - '%s', %d inliers, %.1f deg, %d points (%.1f s)",
                  s.seed.name1.c_str(), s.seed.name2.c_str(), s.seed.num_inliers, s.seed.median_tri_angle_deg,
                  s.seed.num_points3D, s.seed_seconds);
    if (s.seed.depth_backed) {
      say(false, buf);
      std::snprintf(buf, sizeof(buf),
                    "      low parallax: %d of the points placed with the corrected depth priors (prior spread %.1f%%)",
                    s.seed.num_fused_points, 100 * s.seed.prior_sigma);
    }
    say(false, buf);
  } catch (const std::runtime_error& e) {
    s.seed_failure = e.what();
    s.seed_seconds = Seconds(t2);
    say(true, std::string("madsfm mapper: no seed model: ") + e.what() +
                  "; continuing like COLMAP: colmap mapper chooses the initial pair on madsfm's two-view geometries");
  }

  std::string value;
  int min_num_matches = 15;
  if (FindArg(options.colmap_mapper_args, "--Mapper.min_num_matches", &value)) {
    try {
      min_num_matches = std::stoi(value);
    } catch (const std::exception&) {
      throw std::invalid_argument("--Mapper.min_num_matches: '" + value + "' is not an integer");
    }
  }
  s.num_expected = CountConnectedImages(options.two_view.database_path, min_num_matches);

  auto run_attempt = [&](const std::string& name, const std::string& database_path, const std::string& input_path,
                         const std::vector<std::string>& extra) {
    const auto ta = Clock::now();
    MapperAttempt a;
    a.name = name;
    const fs::path dir = out / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    a.log_path = (out / ("colmap_mapper_" + name + ".log")).string();
    fs::remove(a.log_path);
    std::vector<std::string> args = {colmap, "mapper", "--database_path", database_path, "--image_path",
                                     options.image_path};
    if (!input_path.empty()) args.insert(args.end(), {"--input_path", input_path});
    args.insert(args.end(), {"--output_path", dir.string()});
    args.insert(args.end(), options.colmap_mapper_args.begin(), options.colmap_mapper_args.end());
    args.insert(args.end(), extra.begin(), extra.end());
    a.exit_code = RunLogged(args, a.log_path);
    a.model_path = LargestModel(dir, &a.num_registered, &a.num_points3D);
    a.seconds = Seconds(ta);
    std::string extra_text;
    for (const auto& e : extra) extra_text += " " + e;
    std::snprintf(buf, sizeof(buf),
                  "      colmap mapper (%s%s): exit %d, %d of %d images registered, %zu points (%.1f s)",
                  name.c_str(), extra_text.c_str(), a.exit_code, a.num_registered, s.num_expected, a.num_points3D,
                  a.seconds);
    say(false, buf);
    if (a.exit_code != 0 || a.model_path.empty()) {
      say(true, "madsfm mapper: colmap mapper (" + name + ") " +
                    (a.exit_code != 0 ? "failed (exit " + std::to_string(a.exit_code) + ")" : "wrote no model") +
                    "; last lines of " + a.log_path + ":\n" + Tail(a.log_path, 8));
    }
    s.attempts.push_back(a);
    return a;
  };
  auto best_registered = [&]() {
    int n = 0;
    for (const auto& a : s.attempts) n = std::max(n, a.model_path.empty() ? 0 : a.num_registered);
    return n;
  };
  auto done = [&]() { return best_registered() >= s.num_expected && best_registered() > 0; };

  const auto t3 = Clock::now();
  if (s.seeded) {
    const MapperAttempt seeded = run_attempt("seeded", options.two_view.database_path, so.output_path, {});
    // One shared camera whose focal focal_estimator trusts, and bundle adjustment moved it. Run again with the focal
    // fixed (a) on a low-parallax (depth-backed) seed when it moved by more than the aggregate's uncertainty allows
    // (3 robust sigmas of the pairs' log focal over sqrt(pairs), at least 1%): at 1-2 deg of parallax bundle
    // adjustment follows the focal-depth ambiguity of a small baseline, not evidence; or (b) when bundle adjustment
    // determines the focal less well than the pairs did (its Gauss-Newton standard deviation above the aggregate's,
    // 1.4826 x the robust spread over sqrt(pairs)) and moved it by more than that: forward motion, where the epipolar
    // geometry leaves the focal open and the result is set by noise. (One camera only: with one camera per image,
    // refining each focal did better on the per-image walk of docs/benchmarks.md section 9.)
    const bool one_trusted = s.focal.size() == 1 && s.focal[0].updated && s.focal[0].trusted &&
                             !seeded.model_path.empty() &&
                             !FindArg(options.colmap_mapper_args, "--Mapper.ba_refine_focal_length", &value);
    const bool low_parallax = s.seed.depth_backed && options.fix_focal_low_parallax;
    if (one_trusted && (low_parallax || options.fix_focal_ba_uncertain)) {
      colmap::Reconstruction model;
      try {
        model = colmap::ReadReconstruction(seeded.model_path);
      } catch (const std::exception& e) {  // keep the seeded run as it is
        say(true, std::string("madsfm mapper: cannot read the seeded model to check its focal: ") + e.what());
      }
      const FocalChange& fc = s.focal[0];
      const auto cam = model.cameras.find(fc.camera_id);
      if (cam != model.cameras.end()) {
        const colmap::CameraIntrinsics& k = cam->second.intrinsics;
        const double f_ba = 0.5 * (k.FocalX() + k.FocalY());
        std::optional<colmap::FocalUncertainty> u;
        u = colmap::BundleFocalUncertainty(model, fc.camera_id);
        if (u) s.focal_ba_sigma = u->Relative();
        const FocalFixDecision d = DecideFocalFix(fc, f_ba, u, low_parallax, options.fix_focal_ba_uncertain);
        s.focal_drift = d.drift;
        if (d.fix) {
          say(false, d.reason);
          const MapperAttempt fixed = run_attempt("seeded_fixed_focal", options.two_view.database_path, so.output_path,
                                                  {"--Mapper.ba_refine_focal_length", "0"});
          s.focal_fixed = !fixed.model_path.empty() && fixed.num_registered >= seeded.num_registered;
        }
      }
    }
  }
  if ((!s.seeded || options.fallback) && !done()) {
    if (s.seeded) {
      say(true, "madsfm mapper: the seeded run registered " + std::to_string(best_registered()) + " of " +
                    std::to_string(s.num_expected) + " images; trying colmap mapper without the seed");
    }
    const MapperAttempt& a = run_attempt("unseeded", options.two_view.database_path, "", {});
    if (a.model_path.empty()) {
      std::vector<std::string> relaxed;
      if (!FindArg(options.colmap_mapper_args, "--Mapper.init_min_tri_angle", &value)) {
        std::snprintf(buf, sizeof(buf), "%g", options.relaxed_init_min_tri_angle);
        relaxed.insert(relaxed.end(), {"--Mapper.init_min_tri_angle", buf});
      }
      if (!FindArg(options.colmap_mapper_args, "--Mapper.init_min_num_inliers", &value)) {
        relaxed.insert(relaxed.end(),
                       {"--Mapper.init_min_num_inliers", std::to_string(options.relaxed_init_min_num_inliers)});
      }
      if (!relaxed.empty()) run_attempt("unseeded_relaxed", options.two_view.database_path, "", relaxed);
    }
  }
  if (options.fallback && !done()) {
    say(true, "madsfm mapper: best so far " + std::to_string(best_registered()) + " of " +
                  std::to_string(s.num_expected) +
                  " images; trying colmap mapper on COLMAP's own two-view geometries and cameras (a restored copy "
                  "of the database)");
    const std::string copy = (out / "colmap_rows.db").string();
    WriteColmapRowsCopy(options.two_view.database_path, copy);
    run_attempt("colmap_rows", copy, "", {});
  }

  for (size_t i = 0; i < s.attempts.size(); ++i) {
    const MapperAttempt& a = s.attempts[i];
    if (a.model_path.empty()) continue;
    // The fixed-focal rerun replaces the seeded run it corrects when it registers as many images.
    const bool correction = a.name == "seeded_fixed_focal" && s.focal_fixed;
    if (s.kept < 0 || a.num_registered > s.attempts[s.kept].num_registered ||
        (correction && a.num_registered == s.attempts[s.kept].num_registered)) {
      s.kept = static_cast<int>(i);
    }
  }
  if (s.kept < 0) {
    std::string logs;
    for (const auto& a : s.attempts) logs += " " + a.log_path;
    throw std::runtime_error("no colmap mapper run produced a model (also not on COLMAP's own two-view geometries); "
                             "logs:" + logs);
  }
  const MapperAttempt& kept = s.attempts[s.kept];
  s.final_path = (out / "0").string();
  CopyModel(kept.model_path, s.final_path);
  if (s.attempts.size() > 1 || kept.name != "seeded") {
    say(true, "madsfm mapper: keeping the model of the '" + kept.name + "' run (" +
                  std::to_string(kept.num_registered) + " images registered, the most of " +
                  std::to_string(s.attempts.size()) + " colmap mapper run" + (s.attempts.size() > 1 ? "s" : "") + ")");
  }
  const colmap::Reconstruction model = colmap::ReadReconstruction(s.final_path);
  double err = 0;
  for (const auto& [id, p] : model.points3D) err += p.error;
  s.num_points3D = model.points3D.size();
  s.mean_reproj_error = model.points3D.empty() ? 0.0 : err / model.points3D.size();
  std::snprintf(buf, sizeof(buf),
                "[4/4] colmap mapper: %zu images registered, %zu points, mean reprojection error %.3f px (%.1f s)",
                model.images.size(), s.num_points3D, s.mean_reproj_error, Seconds(t3));
  say(false, buf);
  s.total_seconds = Seconds(t0);
  return s;
}

}  // namespace madsfm
