#include "colmap_ext/pipeline/seed_model.h"

#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "colmap_ext/database/database.h"
#include "colmap_ext/model/reconstruction.h"
#include "colmap_ext/pipeline/two_view_estimator.h"
#include "colmap_ext/synthetic/synthetic_project.h"

namespace madsfm {
namespace {

namespace fs = std::filesystem;

// Low-parallax pairs (baselines 0.5-3% of the depth: median triangulation
// angles below 2 deg), calibrated, with depth priors, estimated by
// two_view_estimator.
struct LowParallaxProject {
  std::string dir, db, depths;
  std::vector<SyntheticPair> pairs;
};

// The project folders of this process, removed at its exit.
struct ProjectFolders {
  std::vector<std::string> dirs;
  ~ProjectFolders() {
    std::error_code ec;
    for (const std::string& d : dirs) fs::remove_all(d, ec);
  }
};

LowParallaxProject MakeProject(const std::string& name, uint64_t seed) {
  static ProjectFolders folders;
  LowParallaxProject p;
  // One folder per process: ctest runs the tests of this file at the same time, and several of them build the
  // shared project (a fixed name would let one process delete it while another reads it).
  p.dir = (fs::temp_directory_path() /
           ("madsfm_seed_model_" + name + "_" + std::to_string(seed) + "_" + std::to_string(::getpid())))
              .string();
  fs::remove_all(p.dir);
  folders.dirs.push_back(p.dir);
  colmap::SyntheticProjectOptions o;
  o.output_path = p.dir;
  o.preset = "hard_low_parallax_calibrated";
  o.num_pairs = 12;
  o.min_num_matches = 400;
  o.max_num_matches = 600;
  o.outlier_ratio = 0.2;
  o.calibrated = true;
  o.seed = seed;
  o.keep_pairs = true;
  colmap::SyntheticProject sp = colmap::WriteSyntheticProject(o);
  p.db = sp.database_path;
  p.depths = sp.depth_path;
  p.pairs = std::move(sp.pairs);
  TwoViewEstimatorOptions t;
  t.database_path = p.db;
  t.depth_path = p.depths;
  t.num_threads = 2;
  t.progress = false;
  RunTwoViewEstimatorImpl(t);
  return p;
}

const LowParallaxProject& Project() {
  static const LowParallaxProject p = MakeProject("shared", 3);
  return p;
}

// Median relative depth error in camera 1 of the seed's points against the
// generator's truth, after the best common scale (the seed's gauge is
// arbitrary). Keypoint i of a synthetic pair is its match i.
double SeedDepthError(const LowParallaxProject& project, const SeedModelSummary& s, const std::string& model_dir) {
  const SyntheticPair& pair = project.pairs.at((s.image_id1 - 1) / 2);
  const colmap::Reconstruction model = colmap::ReadReconstruction(model_dir);
  const colmap::ModelImage& im1 = model.images.at(s.image_id1);
  std::vector<double> est, truth;
  for (size_t i = 0; i < im1.point3D_ids.size(); ++i) {
    if (im1.point3D_ids[i] == colmap::kInvalidPoint3DId || !pair.is_inlier[i]) continue;
    est.push_back(model.points3D.at(im1.point3D_ids[i]).xyz.z());  // image 1 is the world frame
    truth.push_back(pair.true_depth0[i]);
  }
  EXPECT_GE(est.size(), 100u);
  std::vector<double> ratio;
  for (size_t i = 0; i < est.size(); ++i) ratio.push_back(truth[i] / est[i]);
  std::nth_element(ratio.begin(), ratio.begin() + ratio.size() / 2, ratio.end());
  const double g = ratio[ratio.size() / 2];
  std::vector<double> err;
  for (size_t i = 0; i < est.size(); ++i) err.push_back(std::abs(g * est[i] / truth[i] - 1.0));
  std::nth_element(err.begin(), err.begin() + err.size() / 2, err.end());
  return err[err.size() / 2];
}

SeedModelOptions Options(const std::string& name, const LowParallaxProject& project = Project()) {
  SeedModelOptions o;
  o.database_path = project.db;
  o.output_path = project.dir + "/" + name;
  return o;
}

TEST(SeedModel, LowParallaxHasNoSeedFromTriangulationAlone) {
  try {
    RunSeedModelImpl(Options("triangulation_only"));
    FAIL() << "expected no seed: every pair is below 4 deg";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("median triangulation angle of at least 4 deg"), std::string::npos)
        << e.what();
  }
}

// Over 12 projects (fixed seeds): most get a depth-backed seed, a 1-4 deg pair whose points, fused with the
// corrected priors, have a smaller depth error than triangulation alone gives on the same pair. The rest get no seed
// from seed_model (the mapper then initialises the way COLMAP does): a project needs one pair among the 12 whose
// corrections are observable and agree with the pose, and over 150 projects (seeds 3-152) 141 had one, 127 of 135
// compared fused points were better and the median ratio of the errors was 0.27-0.44 per 30 projects (measured
// 2026-12-06 with 10 and with 6 Levenberg-Marquardt iterations per local-optimisation fit: the same rates).
TEST(SeedModel, DepthPriorsSeedLowParallaxPairsWithBetterPointsThanTriangulation) {
  int depth_backed = 0, better = 0, compared = 0;
  std::vector<double> ratios;
  for (uint64_t seed = 3; seed < 15; ++seed) {
    const LowParallaxProject project = MakeProject("compare", seed);
    SeedModelOptions depth = Options("depth_backed", project);
    depth.depth_path = project.depths;
    SeedModelSummary with_depth;
    try {
      with_depth = RunSeedModelImpl(depth);
    } catch (const std::runtime_error& e) {
      // No seed: the error names what was required.
      EXPECT_NE(std::string(e.what()).find("with depth priors that agree with the pose"), std::string::npos)
          << e.what();
      continue;
    }
    EXPECT_TRUE(with_depth.depth_backed);
    depth_backed += with_depth.depth_backed;
    EXPECT_LT(with_depth.median_tri_angle_deg, 4.0);
    EXPECT_GE(with_depth.median_tri_angle_deg, 1.0);
    EXPECT_GE(with_depth.num_fused_points, with_depth.num_points3D * 9 / 10);
    EXPECT_GE(with_depth.prior_sigma, 0.02);

    // Triangulation alone (the angle bound lowered to let it through); compared
    // where it seeds the same pair.
    SeedModelOptions tri = Options("triangulated", project);
    tri.min_tri_angle_deg = 1.0;
    const SeedModelSummary triangulated = RunSeedModelImpl(tri);
    EXPECT_FALSE(triangulated.depth_backed);
    EXPECT_EQ(triangulated.num_fused_points, 0);
    if (triangulated.image_id1 != with_depth.image_id1 || triangulated.image_id2 != with_depth.image_id2) continue;
    const double e_depth = SeedDepthError(project, with_depth, depth.output_path);
    const double e_tri = SeedDepthError(project, triangulated, tri.output_path);
    std::printf(
        "seed %d: pair %u-%u, %.2f deg, prior sigma %.3f, depth error "
        "fused %.4f / triangulated %.4f\n",
        static_cast<int>(seed), with_depth.image_id1, with_depth.image_id2, with_depth.median_tri_angle_deg,
        with_depth.prior_sigma, e_depth, e_tri);
    ++compared;
    better += e_depth < e_tri;
    ratios.push_back(e_depth / e_tri);
    fs::remove_all(project.dir);
  }
  std::printf("%d of 12 projects depth-backed; fused points better on %d of %d compared\n", depth_backed, better,
              compared);
  EXPECT_GE(depth_backed, 10);
  ASSERT_GE(compared, 8);
  EXPECT_GE(better, compared * 8 / 10);
  std::sort(ratios.begin(), ratios.end());
  EXPECT_LT(ratios[ratios.size() / 2], 0.8) << "median ratio of fused to triangulated depth error";
}

TEST(SeedModel, DepthBackedSeedsCanBeSwitchedOff) {
  SeedModelOptions o = Options("depth_off");
  o.depth_path = Project().depths;
  o.min_depth_tri_angle_deg = 0.0;
  EXPECT_THROW(RunSeedModelImpl(o), std::runtime_error);
}

TEST(SeedModel, WithoutSidecarsNoPairIsDepthBacked) {
  SeedModelOptions o = Options("no_sidecars");
  o.depth_path = Project().dir + "/no_such_folder";
  // No sidecar means no prior for any keypoint: no pair is depth-backed, and
  // the error says what was required.
  try {
    RunSeedModelImpl(o);
    FAIL() << "expected no seed";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("with depth priors that agree with the pose"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace madsfm
