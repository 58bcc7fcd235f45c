// Sharded two_view_estimator runs + merge_shards (issue 7): the merged database equals the single-process run,
// merging is idempotent, foreign shards are refused without a write, uncovered pairs are reported, a killed shard
// task resumes, and a shard task never changes the database.
#include "colmap_ext/pipeline/merge_shards.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "colmap_ext/database/database.h"
#include "colmap_ext/pipeline/two_view_estimator.h"
#include "colmap_ext/shard/shard_file.h"
#include "colmap_ext/shard/shard_plan.h"
#include "colmap_ext/synthetic/synthetic_project.h"
#include "testing/colmap_database_builder.h"
#include "testing/error_of.h"
#include "testing/temp_dir.h"

namespace madsfm {
namespace {

namespace fs = std::filesystem;
using testing::ErrorOf;

constexpr int kNumPairs = 16;
constexpr int kMinNumMatches = 60;  // the project has 30-150 matches per pair: some pairs are skipped

// One synthetic project per test (name), with COLMAP's own rows for a few pairs (so the backup table has content).
struct Project {
  std::shared_ptr<testing::TempDir> scratch;  // removed with the last copy of the project
  std::string dir, db, depths;
};

Project MakeProject(const std::string& name, uint64_t seed = 11) {
  Project p;
  p.scratch = std::make_shared<testing::TempDir>("merge_" + name);
  p.dir = p.scratch->Sub("project");
  colmap::SyntheticProjectOptions o;
  o.output_path = p.dir;
  o.num_pairs = kNumPairs;
  o.min_num_matches = 30;
  o.max_num_matches = 150;
  o.seed = seed;
  const colmap::SyntheticProject sp = colmap::WriteSyntheticProject(o);
  p.db = sp.database_path;
  p.depths = sp.depth_path;
  // COLMAP's rows (config 2, a few inliers) for the first three pairs.
  testing::ExecSql(p.db,
                   "INSERT INTO two_view_geometries(pair_id, rows, cols, data, config) "
                   "SELECT pair_id, 1, 2, x'0000000000000000', 2 FROM matches ORDER BY pair_id LIMIT 3");
  return p;
}

std::string CopyDb(const Project& p, const std::string& name) {
  const std::string path = p.dir + "/" + name + ".db";
  fs::copy_file(p.db, path, fs::copy_options::overwrite_existing);
  return path;
}

TwoViewEstimatorOptions Options(const Project& p, const std::string& db) {
  TwoViewEstimatorOptions o;
  o.database_path = db;
  o.depth_path = p.depths;
  o.min_num_matches = kMinNumMatches;
  o.num_threads = 2;
  o.progress = false;
  o.estimator.seed = 5;
  return o;
}

// Runs every shard of a split (with the given thread count) and returns the shard files.
std::vector<std::string> RunShards(const Project& p, const std::string& db, int num_shards, int threads = 1,
                                   const std::string& tag = "s") {
  std::vector<std::string> files;
  for (int k = 0; k < num_shards; ++k) {
    TwoViewEstimatorOptions o = Options(p, db);
    o.num_shards = num_shards;
    o.shard_index = k;
    o.num_threads = threads;
    o.shard_path = p.dir + "/" + tag + "_" + std::to_string(k) + "_of_" + std::to_string(num_shards) + ".sqlite";
    RunTwoViewEstimatorImpl(o);
    files.push_back(o.shard_path);
  }
  return files;
}

MergeShardsSummary Merge(const std::string& db, const std::vector<std::string>& shards,
                         const std::string& uncovered = "") {
  MergeShardsOptions m;
  m.database_path = db;
  m.shard_paths = shards;
  m.uncovered_path = uncovered;
  m.progress = false;
  return MergeShards(m);
}

// Every table of the database, dumped (all columns, blobs as hex).
std::string DumpAll(const std::string& db) {
  std::ostringstream out;
  std::vector<std::string> tables = colmap::Database::Open(db, true)->ListTables();
  std::sort(tables.begin(), tables.end());
  for (const std::string& t : tables) out << "== " << t << "\n" << testing::DumpTable(db, t);
  return out.str();
}

std::string FileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(MergeShards, MergedDatabaseEqualsTheSingleProcessRun) {
  const Project p = MakeProject("equal");
  const std::string single = CopyDb(p, "single");
  const TwoViewEstimatorSummary s = RunTwoViewEstimatorImpl(Options(p, single));
  ASSERT_GT(s.num_skipped_few_matches, 0);  // the split must also leave these out
  ASSERT_GT(s.num_estimated, 8);
  const std::string expected = DumpAll(single);
  ASSERT_NE(expected.find("== madsfm_backup_two_view_geometries"), std::string::npos);
  for (int num_shards : {1, 3, 4}) {
    const std::string merged = CopyDb(p, "merged" + std::to_string(num_shards));
    const auto files =
        RunShards(p, merged, num_shards, /*threads=*/1 + num_shards % 2, "eq" + std::to_string(num_shards));
    const MergeShardsSummary m = Merge(merged, files);
    EXPECT_EQ(m.num_results, kNumPairs - s.num_skipped_few_matches);
    EXPECT_EQ(m.num_geometries, s.num_estimated);
    EXPECT_TRUE(m.uncovered.empty());
    EXPECT_TRUE(m.missing_shard_indices.empty());
    EXPECT_EQ(DumpAll(merged), expected) << num_shards << " shards";
    EXPECT_EQ(testing::IntegrityCheck(merged), "ok");
  }
}

// On a database with COLMAP main's camera1 / camera2 columns the estimated cameras travel through the shard files:
// the merged database equals the single-process run, camera blobs included.
TEST(MergeShards, EstimatedCamerasGoThroughTheShards) {
  const Project p = MakeProject("cameras");
  testing::ExecSql(p.db, "ALTER TABLE two_view_geometries ADD COLUMN camera1 BLOB; "
                         "ALTER TABLE two_view_geometries ADD COLUMN camera2 BLOB");
  const std::string single = CopyDb(p, "single");
  const TwoViewEstimatorSummary s = RunTwoViewEstimatorImpl(Options(p, single));
  ASSERT_GT(s.num_estimated, 8);
  auto db = colmap::Database::Open(single, true);
  int with_cameras = 0;
  for (const auto& [pair_id, n] : db->ReadMatchedPairs()) {
    const auto g = db->ReadTwoViewGeometry(pair_id);
    with_cameras += g && g->camera1.has_value() && g->camera2.has_value();
  }
  db.reset();
  EXPECT_EQ(with_cameras, s.num_estimated);  // the project's cameras have no focal prior: focal modes everywhere
  const std::string merged = CopyDb(p, "merged");
  Merge(merged, RunShards(p, merged, 3, 1, "cam"));
  EXPECT_EQ(DumpAll(merged), DumpAll(single));
}

TEST(MergeShards, MergingTwiceChangesNothing) {
  const Project p = MakeProject("twice");
  const std::string db = CopyDb(p, "db");
  const auto files = RunShards(p, db, 2);
  Merge(db, files);
  const std::string once = DumpAll(db);
  const MergeShardsSummary again = Merge(db, files);
  EXPECT_EQ(DumpAll(db), once);
  EXPECT_TRUE(again.uncovered.empty());
  // COLMAP's original rows are still the ones backed up, not madsfm's.
  EXPECT_GE(colmap::Database::Open(db)->RestoreTwoViewGeometries(), 1);
  EXPECT_EQ(testing::DumpTable(db, "two_view_geometries"), testing::DumpTable(p.db, "two_view_geometries"));
}

TEST(MergeShards, AShardTaskOnlyReadsTheDatabase) {
  const Project p = MakeProject("readonly");
  const std::string db = CopyDb(p, "db");
  const std::string before = FileBytes(db);
  fs::permissions(db, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  const auto files = RunShards(p, db, 2);
  fs::permissions(db, fs::perms::owner_read | fs::perms::owner_write);
  EXPECT_EQ(FileBytes(db), before);
  EXPECT_FALSE(fs::exists(db + "-journal"));
  EXPECT_GT(colmap::ShardFile::Open(files[0], true)->ResultPairs().size(), 0u);
}

TEST(MergeShards, RefusesShardsOfAnotherDatabaseOptionsOrSplitWithoutWriting) {
  const Project p = MakeProject("refuse");
  const Project other = MakeProject("refuse_other", 99);
  const std::string db = CopyDb(p, "db");
  const auto files = RunShards(p, db, 2, 1, "good");
  const std::string before = DumpAll(db);

  const auto foreign = RunShards(other, other.db, 2, 1, "foreign");
  std::string e = ErrorOf([&] { Merge(db, {files[0], foreign[1]}); });
  EXPECT_NE(e.find("shard file '" + foreign[1] + "' was made from another database"), std::string::npos) << e;

  TwoViewEstimatorOptions o = Options(p, db);
  o.num_shards = 2;
  o.shard_index = 1;
  o.estimator.epipolar_threshold = 3;
  o.shard_path = p.dir + "/other_options.sqlite";
  RunTwoViewEstimatorImpl(o);
  e = ErrorOf([&] { Merge(db, {files[0], o.shard_path}); });
  EXPECT_NE(e.find("shard file '" + o.shard_path + "' was made with other options than '" + files[0] + "'"),
            std::string::npos) << e;

  const auto three = RunShards(p, db, 3, 1, "three");
  e = ErrorOf([&] { Merge(db, {files[0], three[1]}); });
  EXPECT_NE(e.find("shard file '" + three[1] + "' (shard 1 of 3) belongs to another split"), std::string::npos) << e;

  e = ErrorOf([&] { Merge(db, {files[0], files[0]}); });
  EXPECT_NE(e.find("shard 0 of 2 given twice"), std::string::npos) << e;

  e = ErrorOf([&] { Merge(db, {files[0], p.db}); });
  EXPECT_NE(e.find("'" + p.db + "' is not a madsfm shard file"), std::string::npos) << e;

  EXPECT_EQ(DumpAll(db), before);  // nothing written by any refused merge
}

TEST(MergeShards, ReportsThePairsNoShardCoveredThenCompletes) {
  const Project p = MakeProject("uncovered");
  const std::string db = CopyDb(p, "db");
  const std::string single = CopyDb(p, "single");
  RunTwoViewEstimatorImpl(Options(p, single));
  const auto files = RunShards(p, db, 4);

  // Shards 1 and 3 missing: exactly their pairs are uncovered, and listed as a pair list.
  const std::string list = p.dir + "/uncovered.txt";
  const MergeShardsSummary partial = Merge(db, {files[0], files[2]}, list);
  EXPECT_EQ(partial.missing_shard_indices, (std::vector<int>{1, 3}));
  std::set<colmap::pair_t> expected;
  for (int k : {1, 3}) {
    for (colmap::pair_t pr : colmap::ShardFile::Open(files[k], true)->AssignedPairs()) expected.insert(pr);
  }
  EXPECT_EQ(std::set<colmap::pair_t>(partial.uncovered.begin(), partial.uncovered.end()), expected);
  EXPECT_TRUE(partial.coverage_from_database);
  auto db_handle = colmap::Database::Open(db, true);
  std::map<colmap::image_t, std::string> names;
  for (const auto& im : db_handle->ReadImages()) names[im.image_id] = im.name;
  const auto listed = ReadImagePairList(list);
  EXPECT_EQ(listed.size(), 2 * expected.size());
  for (colmap::pair_t pr : expected) {
    colmap::image_t a, b;
    colmap::PairIdToImagePair(pr, &a, &b);
    EXPECT_TRUE(listed.count({names[a], names[b]})) << names[a] << " " << names[b];
  }
  db_handle.reset();

  // The rest arrives later: now everything is covered (the first two shards count as done in the database) and the
  // database equals the single-process run.
  const MergeShardsSummary rest = Merge(db, {files[1], files[3]});
  EXPECT_TRUE(rest.uncovered.empty());
  EXPECT_EQ(rest.num_already_done, static_cast<long long>(
                                       colmap::ShardFile::Open(files[0], true)->ResultPairs().size() +
                                       colmap::ShardFile::Open(files[2], true)->ResultPairs().size()));
  EXPECT_EQ(DumpAll(db), DumpAll(single));
}

TEST(MergeShards, AKilledShardTaskResumesFromItsFile) {
  const Project p = MakeProject("resume");
  const std::string db = CopyDb(p, "db");
  const std::string single = CopyDb(p, "single");
  RunTwoViewEstimatorImpl(Options(p, single));
  auto files = RunShards(p, db, 2);
  // As if the task of shard 1 had been killed after its first batches: drop half of its results.
  const size_t total = colmap::ShardFile::Open(files[1], true)->ResultPairs().size();
  ASSERT_GE(total, 4u);
  testing::ExecSql(files[1], "DELETE FROM madsfm_shard_results WHERE pair_id IN (SELECT pair_id FROM "
                             "madsfm_shard_results ORDER BY pair_id DESC LIMIT " + std::to_string(total / 2) + ")");
  EXPECT_EQ(Merge(db, files).uncovered.size(), total / 2);

  TwoViewEstimatorOptions o = Options(p, db);
  o.num_shards = 2;
  o.shard_index = 1;
  o.shard_path = files[1];
  const TwoViewEstimatorSummary rerun = RunTwoViewEstimatorImpl(o);
  EXPECT_EQ(rerun.num_skipped_done, static_cast<int>(total - total / 2));
  EXPECT_EQ(rerun.num_estimated + rerun.num_failed, static_cast<int>(total / 2));
  EXPECT_TRUE(Merge(db, files).uncovered.empty());
  EXPECT_EQ(DumpAll(db), DumpAll(single));

  // The same shard path with other options is refused (naming the file) unless --overwrite.
  o.estimator.reproj_threshold = 4;
  const std::string e = ErrorOf([&] { RunTwoViewEstimatorImpl(o); });
  EXPECT_NE(e.find("shard file '" + files[1] + "' exists and was made from other options"), std::string::npos) << e;
  o.overwrite = true;
  EXPECT_EQ(RunTwoViewEstimatorImpl(o).num_skipped_done, 0);
  EXPECT_EQ(colmap::ShardFile::Open(files[1], true)->info().options_fingerprint, OptionsFingerprint(o));
}

TEST(MergeShards, TheDepthFolderCountsByLocationNotSpelling) {
  const Project p = MakeProject("spelling");
  TwoViewEstimatorOptions a = Options(p, p.db), b = a, c = a;
  b.depth_path = p.depths + "/";
  c.depth_path = p.dir + "/./depths";
  EXPECT_EQ(OptionsFingerprint(a), OptionsFingerprint(b));
  EXPECT_EQ(OptionsFingerprint(a), OptionsFingerprint(c));
  const fs::path old_cwd = fs::current_path();
  fs::current_path(p.dir);
  TwoViewEstimatorOptions relative = a;
  relative.depth_path = "depths";
  const std::string relative_fingerprint = OptionsFingerprint(relative);
  fs::current_path(old_cwd);
  EXPECT_EQ(relative_fingerprint, OptionsFingerprint(a));
  TwoViewEstimatorOptions other = a;
  other.depth_path = p.dir;
  EXPECT_NE(OptionsFingerprint(other), OptionsFingerprint(a));
}

// Every estimator option that changes a result changes the fingerprint, so a rerun with it re-estimates the pairs.
TEST(MergeShards, EveryResultChangingEstimatorOptionChangesTheFingerprint) {
  const Project p = MakeProject("fingerprint");
  const TwoViewEstimatorOptions a = Options(p, p.db);
  const std::vector<std::pair<std::string, std::function<void(HybridEstimatorOptions*)>>> changes = {
      {"reproj_threshold", [](HybridEstimatorOptions* e) { e->reproj_threshold += 1; }},
      {"epipolar_threshold", [](HybridEstimatorOptions* e) { e->epipolar_threshold += 1; }},
      {"sampson_weight", [](HybridEstimatorOptions* e) { e->sampson_weight += 1; }},
      {"solvers", [](HybridEstimatorOptions* e) { e->solvers = SolverChoice::kPointsOnly; }},
      {"scoring", [](HybridEstimatorOptions* e) { e->scoring = ScoringMode::kSampsonOnly; }},
      {"estimate_shift", [](HybridEstimatorOptions* e) { e->estimate_shift = !e->estimate_shift; }},
      {"sampson_cheirality", [](HybridEstimatorOptions* e) { e->sampson_cheirality = !e->sampson_cheirality; }},
      {"cheirality_min_parallax", [](HybridEstimatorOptions* e) { e->cheirality_min_parallax += 0.25; }},
      {"min_iterations", [](HybridEstimatorOptions* e) { e->min_iterations += 1; }},
      {"min_iterations_two_focal_points", [](HybridEstimatorOptions* e) { e->min_iterations_two_focal_points += 1; }},
      {"min_iterations_shared_focal_points",
       [](HybridEstimatorOptions* e) { e->min_iterations_shared_focal_points += 1; }},
      {"max_iterations", [](HybridEstimatorOptions* e) { e->max_iterations += 1; }},
      {"confidence", [](HybridEstimatorOptions* e) { e->confidence = 0.99; }},
      {"guided_sampling_fraction", [](HybridEstimatorOptions* e) { e->guided_sampling_fraction = 0.5; }},
      {"lo_skip_same_basin", [](HybridEstimatorOptions* e) { e->lo_skip_same_basin = false; }},
      {"num_lo_steps", [](HybridEstimatorOptions* e) { e->num_lo_steps += 1; }},
      {"num_lo_lsq_steps", [](HybridEstimatorOptions* e) { e->num_lo_lsq_steps += 1; }},
      {"lo_threshold_multiplier", [](HybridEstimatorOptions* e) { e->lo_threshold_multiplier += 1; }},
      {"lo_inner_sample_multiplier", [](HybridEstimatorOptions* e) { e->lo_inner_sample_multiplier += 1; }},
      {"lo_lsq_sample_size", [](HybridEstimatorOptions* e) { e->lo_lsq_sample_size += 1; }},
      {"lo_first_fit_sample_size", [](HybridEstimatorOptions* e) { e->lo_first_fit_sample_size = 0; }},
      {"lo_starting_iterations", [](HybridEstimatorOptions* e) { e->lo_starting_iterations += 1; }},
      {"lo_max_lm_iterations", [](HybridEstimatorOptions* e) { e->lo_max_lm_iterations += 1; }},
      {"lo_max_lm_iterations_two_focal", [](HybridEstimatorOptions* e) { e->lo_max_lm_iterations_two_focal += 1; }},
      {"alt_basin_lo_margin", [](HybridEstimatorOptions* e) { e->alt_basin_lo_margin = 0.1; }},
      {"planar_twin_min_support", [](HybridEstimatorOptions* e) { e->planar_twin_min_support = 0.0; }},
      {"low_parallax_sampson_factor", [](HybridEstimatorOptions* e) { e->low_parallax_sampson_factor = 1.0; }},
      {"low_parallax_noise_ratio", [](HybridEstimatorOptions* e) { e->low_parallax_noise_ratio += 1; }},
      {"mixed_refinement_depth_from_triangulation",
       [](HybridEstimatorOptions* e) { e->mixed_refinement_depth_from_triangulation = false; }},
      {"low_parallax_final_reprojection_weight",
       [](HybridEstimatorOptions* e) { e->low_parallax_final_reprojection_weight = 0.5; }},
      {"final_refinement", [](HybridEstimatorOptions* e) { e->final_refinement = !e->final_refinement; }},
      {"final_max_lm_iterations", [](HybridEstimatorOptions* e) { e->final_max_lm_iterations += 1; }},
      {"final_reprojection_weight", [](HybridEstimatorOptions* e) { e->final_reprojection_weight = 0.5; }},
      {"epipolar_focal_max_sigma", [](HybridEstimatorOptions* e) { e->epipolar_focal_max_sigma = 0.0; }},
      {"epipolar_focal_wide_sigma", [](HybridEstimatorOptions* e) { e->epipolar_focal_wide_sigma = 0.0; }},
      {"final_cauchy_ratio", [](HybridEstimatorOptions* e) { e->final_cauchy_ratio = 0.0; }},
      {"epipolar_check_ratio", [](HybridEstimatorOptions* e) { e->epipolar_check_ratio = 1.5; }},
      {"retry_depth_less", [](HybridEstimatorOptions* e) { e->retry_depth_less = !e->retry_depth_less; }},
      {"scale_only_fallback", [](HybridEstimatorOptions* e) { e->scale_only_fallback = !e->scale_only_fallback; }},
      {"max_shift_ratio", [](HybridEstimatorOptions* e) { e->max_shift_ratio += 1; }},
      {"final_depth_fit", [](HybridEstimatorOptions* e) { e->final_depth_fit = !e->final_depth_fit; }},
      {"depth_fit_regression", [](HybridEstimatorOptions* e) { e->depth_fit_regression = !e->depth_fit_regression; }},
      {"low_parallax_depth_fit_regression",
       [](HybridEstimatorOptions* e) { e->low_parallax_depth_fit_regression = !e->low_parallax_depth_fit_regression; }},
      {"depth_fit_regression_in_bound",
       [](HybridEstimatorOptions* e) { e->depth_fit_regression_in_bound = !e->depth_fit_regression_in_bound; }},
      {"focal_depth_from_joint",
       [](HybridEstimatorOptions* e) { e->focal_depth_from_joint = !e->focal_depth_from_joint; }},
      {"max_depth_sigma", [](HybridEstimatorOptions* e) { e->max_depth_sigma *= 2; }},
      {"seed", [](HybridEstimatorOptions* e) { e->seed += 1; }},
  };
  std::set<std::string> seen = {OptionsFingerprint(a)};
  for (const auto& [name, change] : changes) {
    TwoViewEstimatorOptions b = a;
    change(&b.estimator);
    EXPECT_TRUE(seen.insert(OptionsFingerprint(b)).second) << name << " does not change the fingerprint";
  }
  // Options that do not change a result leave it alone.
  TwoViewEstimatorOptions c = a;
  c.num_threads = 1;
  c.batch_size = 7;
  c.progress = !c.progress;
  c.on_batch_written = [](int, int) {};
  EXPECT_EQ(OptionsFingerprint(c), OptionsFingerprint(a));
}

TEST(MergeShards, ShardOptionsAreChecked) {
  const Project p = MakeProject("options");
  TwoViewEstimatorOptions o = Options(p, p.db);
  o.num_shards = 0;
  EXPECT_NE(ErrorOf([&] { RunTwoViewEstimatorImpl(o); }).find("--num_shards must be >= 1"), std::string::npos);
  o.num_shards = 4;
  o.shard_index = 4;
  o.shard_path = p.dir + "/x.sqlite";
  EXPECT_NE(ErrorOf([&] { RunTwoViewEstimatorImpl(o); }).find("--shard_index 4 is not in [0, --num_shards = 4)"),
            std::string::npos);
  o.shard_index = 1;
  o.shard_path.clear();
  EXPECT_NE(ErrorOf([&] { RunTwoViewEstimatorImpl(o); }).find("--num_shards > 1 needs --shard_path"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(p.dir + "/x.sqlite"));
  MergeShardsOptions m;
  m.database_path = p.db;
  EXPECT_NE(ErrorOf([&] { MergeShards(m); }).find("no shard files given"), std::string::npos);
}

}  // namespace
}  // namespace madsfm
