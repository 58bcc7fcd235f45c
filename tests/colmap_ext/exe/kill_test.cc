// Crash safety of `madsfm two_view_estimator`: a run on a database of 300 synthetic pairs (write transactions of 16
// pairs, in a forked child running RunTwoViewEstimatorImpl) is SIGKILLed at seeded random moments spread over the
// pairs (anchored to its progress: after a random batch, within a random part of the next), restarted on the same
// database and killed again, five times. After every kill the database must be healthy (integrity check "ok"), hold
// whole batches only (the done pairs are a prefix of the pair order whose length is a multiple of the batch size,
// each with its final rows), keep COLMAP's original rows of every other pair, and a last rerun of the CLI binary
// must end with tables byte-identical to an uninterrupted reference run of the CLI. Shard tasks (CLI with --shard_path --batch_size 16) are killed too: their shard files must hold
// whole batches, resume, and merge to the reference tables.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "colmap_ext/pipeline/two_view_estimator.h"
#include "madsfm/io/depth_map_io.h"
#include "madsfm/synthetic/two_view_scene.h"
#include "testing/colmap_database_builder.h"

extern char** environ;

namespace madsfm {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr int kNumPairs = 300;
constexpr int kBatchSize = 16;
constexpr int kNumKills = 5;
// RANSAC cap (default 10000) lowered to keep the runs short: the pairs with shuffled matches run to the cap.
constexpr int kMaxIterations = 2000;

struct KillProject {
  std::string dir, original_db, depths;
};

// 300 independent synthetic pairs (images 2k+1, 2k+2, one SIMPLE_PINHOLE camera per pair without focal prior),
// 150 identity matches with 30% outliers, depth sidecars. Every 25th pair gets shuffled matches (mostly wrong, so
// it may fail and keep COLMAP's row). COLMAP's own two_view_geometries rows (config 3, all matches) exist for the
// pairs whose second image id is not a multiple of 3, so "intact original rows" covers both present and absent rows.
// One folder per process: ctest runs the two kill tests of this file at the same time.
std::string KillProjectDir() {
  return (fs::temp_directory_path() / ("madsfm_kill_test_" + std::to_string(::getpid()))).string();
}

const KillProject& Project() {
  static const KillProject project = [] {
    KillProject p;
    p.dir = KillProjectDir();
    fs::remove_all(p.dir);
    fs::create_directories(p.dir + "/depths");
    p.original_db = p.dir + "/original.db";
    p.depths = p.dir + "/depths";
    testing::ColmapDatabaseBuilder b(p.original_db);
    SyntheticPairOptions opt = *SyntheticPairPreset("indoor_shared_focal");
    opt.num_matches = 150;
    opt.min_outlier_ratio = opt.max_outlier_ratio = 0.3;
    const std::vector<SyntheticPair> pairs = GenerateTwoViewSet(opt, kNumPairs, 23);
    b.Exec("BEGIN");
    for (int k = 0; k < kNumPairs; ++k) {
      const PairData& d = pairs[k].pair;
      const uint32_t cam = b.AddCamera(0, d.width0, d.height0,
                                       {1.2 * std::max(d.width0, d.height0), d.K0(0, 2) + 0.5, d.K0(1, 2) + 0.5},
                                       false);
      const std::string n1 = "kill" + std::to_string(k) + "_a.png", n2 = "kill" + std::to_string(k) + "_b.png";
      const uint32_t i1 = b.AddImage(n1, cam), i2 = b.AddImage(n2, cam);
      std::vector<Eigen::Vector2d> k1, k2;
      std::vector<std::array<uint32_t, 2>> matches;
      const uint32_t n = static_cast<uint32_t>(d.p0.size());
      for (uint32_t i = 0; i < n; ++i) {
        k1.push_back(d.p0[i] + Eigen::Vector2d(0.5, 0.5));
        k2.push_back(d.p1[i] + Eigen::Vector2d(0.5, 0.5));
        matches.push_back({i, k % 25 == 7 ? (i * 37 + 11) % n : i});
      }
      b.AddKeypoints(i1, k1);
      b.AddKeypoints(i2, k2);
      b.AddMatches(i1, i2, matches);
      WriteDepthMapNpy(*d.depth0, p.depths + "/" + n1 + ".npy");
      WriteDepthMapNpy(*d.depth1, p.depths + "/" + n2 + ".npy");
    }
    b.Exec("INSERT INTO two_view_geometries(pair_id, rows, cols, data, config) SELECT pair_id, rows, cols, data, 3 "
           "FROM matches WHERE (pair_id % 2147483647) % 3 != 0");
    b.Exec("COMMIT");
    return p;
  }();
  return project;
}

// The project folder holds ~180 MB of depth maps and both tests of this file use it: it is removed once, after the
// last test of the binary (a test removing it would break the other one when both run in one process), and kept when
// a test failed, to investigate.
class KillProjectCleanup : public ::testing::Environment {
 public:
  void TearDown() override {
    if (::testing::UnitTest::GetInstance()->failed_test_count() == 0) fs::remove_all(KillProjectDir());
  }
};
::testing::Environment* const kKillProjectCleanup = ::testing::AddGlobalTestEnvironment(new KillProjectCleanup);

std::string CopyDatabase(const std::string& name) {
  const std::string path = Project().dir + "/" + name + ".db";
  fs::remove(path);
  fs::remove(path + "-journal");
  fs::remove(path + ".log");
  fs::copy_file(Project().original_db, path);
  return path;
}

// Starts `madsfm two_view_estimator` on `db` with its default options (one write transaction per 256 pairs)
// through the CLI binary, stdout/stderr to db.log; returns the child's pid.
pid_t StartCli(const std::string& db, const std::vector<std::string>& extra_args = {}) {
  std::vector<std::string> args = {MADSFM_CLI_PATH, "two_view_estimator", "--database_path", db,
                                   "--depth_path",  Project().depths,    "--num_threads",   "2",
                                   "--max_iterations", std::to_string(kMaxIterations)};
  args.insert(args.end(), extra_args.begin(), extra_args.end());
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  const std::string log = db + ".log";
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) {
    ADD_FAILURE() << "posix_spawn " << argv[0] << ": " << std::strerror(rc);
    return -1;
  }
  return pid;
}

// Forks a child that runs the estimator on `db` with the CLI's options (seed 0, 2 threads, the same depth folder
// and max_iterations, hence the same options fingerprint) but batches of kBatchSize pairs, calling
// RunTwoViewEstimatorImpl directly. The test process is single-threaded and holds no SQLite connection when it forks.
// Returns the child's pid.
// notify_fd >= 0: the child writes one byte to it after every batch it has written (on_batch_written).
pid_t StartForkedEstimator(const std::string& db, int notify_fd) {
  TwoViewEstimatorOptions o;
  o.database_path = db;
  o.depth_path = Project().depths;
  o.num_threads = 2;
  o.batch_size = kBatchSize;
  o.progress = false;
  o.estimator.seed = 0;
  o.estimator.max_iterations = kMaxIterations;
  if (notify_fd >= 0) {
    o.on_batch_written = [notify_fd](int, int) {
      const char byte = 1;
      while (::write(notify_fd, &byte, 1) < 0 && errno == EINTR) {
      }
    };
  }
  std::fflush(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    int code = 0;
    try {
      RunTwoViewEstimatorImpl(o);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "forked two_view_estimator: %s\n", e.what());
      code = 1;
    }
    _exit(code);
  }
  if (pid < 0) ADD_FAILURE() << "fork: " << std::strerror(errno);
  return pid;
}

int WaitFor(pid_t pid) {
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return status;
}

// Runs the CLI estimator to completion; returns the wall time in seconds, asserting exit code 0.
double RunCliToCompletion(const std::string& db) {
  const auto t0 = Clock::now();
  const pid_t pid = StartCli(db);
  if (pid < 0) return 0;
  const int status = WaitFor(pid);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "status " << status << ", see " << db << ".log";
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Opens read-write (as COLMAP would after a crash: a hot rollback journal is rolled back) and returns every row of
// `table` keyed by pair_id, all columns rendered ("" if the table does not exist).
std::map<int64_t, std::string> RowsByPair(const std::string& path, const std::string& table) {
  std::map<int64_t, std::string> rows;
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE, nullptr) != SQLITE_OK) {
    ADD_FAILURE() << "cannot open " << path;
    sqlite3_close(db);
    return rows;
  }
  sqlite3_stmt* st = nullptr;
  if (sqlite3_prepare_v2(db, ("SELECT * FROM " + table).c_str(), -1, &st, nullptr) == SQLITE_OK) {
    while (sqlite3_step(st) == SQLITE_ROW) {
      std::ostringstream out;
      for (int c = 0; c < sqlite3_column_count(st); ++c) {
        const int type = sqlite3_column_type(st, c);
        if (type == SQLITE_BLOB) {
          const auto* b = static_cast<const unsigned char*>(sqlite3_column_blob(st, c));
          char hex[3];
          for (int i = 0; i < sqlite3_column_bytes(st, c); ++i) {
            std::snprintf(hex, sizeof(hex), "%02x", b[i]);
            out << hex;
          }
        } else if (type == SQLITE_NULL) {
          out << "NULL";
        } else {
          out << sqlite3_column_text(st, c);
        }
        out << '|';
      }
      rows[sqlite3_column_int64(st, 0)] = out.str();
    }
  }
  sqlite3_finalize(st);
  sqlite3_close(db);
  return rows;
}

// pair_id -> (status, num_inliers_sampson) of madsfm's table; empty without the table.
std::map<int64_t, std::pair<int, int>> MadsfmStatus(const std::string& path) {
  std::map<int64_t, std::pair<int, int>> out;
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
    sqlite3_stmt* st = nullptr;
    if (sqlite3_prepare_v2(db, "SELECT pair_id, status, num_inliers_sampson FROM madsfm_two_view_geometries", -1, &st,
                           nullptr) == SQLITE_OK) {
      while (sqlite3_step(st) == SQLITE_ROW) {
        out[sqlite3_column_int64(st, 0)] = {sqlite3_column_int(st, 1), sqlite3_column_int(st, 2)};
      }
    }
    sqlite3_finalize(st);
  }
  sqlite3_close(db);
  return out;
}

// "rows" column of every two_view_geometries row.
std::map<int64_t, int> GeometryRowCounts(const std::string& path) {
  std::map<int64_t, int> out;
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
    sqlite3_stmt* st = nullptr;
    if (sqlite3_prepare_v2(db, "SELECT pair_id, rows FROM two_view_geometries", -1, &st, nullptr) == SQLITE_OK) {
      while (sqlite3_step(st) == SQLITE_ROW) out[sqlite3_column_int64(st, 0)] = sqlite3_column_int(st, 1);
    }
    sqlite3_finalize(st);
  }
  sqlite3_close(db);
  return out;
}

// "" when the two dumps are equal, else the first differing line of each (cut to 160 characters).
std::string FirstDifference(const std::string& a, const std::string& b) {
  if (a == b) return "";
  std::istringstream sa(a), sb(b);
  std::string la, lb;
  for (int line = 1;; ++line) {
    const bool ha = static_cast<bool>(std::getline(sa, la)), hb = static_cast<bool>(std::getline(sb, lb));
    if (ha != hb || la != lb) {
      return "line " + std::to_string(line) + ": '" + (ha ? la.substr(0, 160) : "<end>") + "' vs '" +
             (hb ? lb.substr(0, 160) : "<end>") + "'";
    }
  }
}

std::string Find(const std::map<int64_t, std::string>& rows, int64_t key) {
  const auto it = rows.find(key);
  return it == rows.end() ? "<no row>" : it->second;
}

// A killed shard task (SIGKILL mid-run) leaves a healthy shard file of whole batches; rerunning the task resumes
// it, and merging both shards gives tables byte-identical to the single-process CLI run.
TEST(TwoViewEstimatorKill, KilledShardTaskResumesAndTheMergeEqualsTheReferenceRun) {
  const std::string ref = CopyDatabase("shard_reference");
  const double ref_seconds = RunCliToCompletion(ref);
  const std::string db = CopyDatabase("sharded");
  const std::string before = testing::DumpTable(db, "two_view_geometries");
  std::vector<std::string> shards;
  int num_killed = 0;
  for (int k = 0; k < 2; ++k) {
    shards.push_back(Project().dir + "/shard_" + std::to_string(k) + ".sqlite");
    fs::remove(shards.back());
    const std::vector<std::string> shard_args = {"--num_shards", "2", "--shard_index", std::to_string(k),
                                                 "--shard_path", shards.back(), "--batch_size",
                                                 std::to_string(kBatchSize)};
    // Kill each task at about a quarter of its expected time (half the pairs of the reference run).
    const pid_t pid = StartCli(db, shard_args);
    ASSERT_GT(pid, 0);
    std::this_thread::sleep_for(std::chrono::duration<double>(0.25 * ref_seconds));
    ::kill(pid, SIGKILL);
    const int status = WaitFor(pid);
    num_killed += WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL;
    if (fs::exists(shards.back())) {
      const std::string count_sql = "SELECT COUNT(*) FROM madsfm_shard_results";
      sqlite3* h = nullptr;
      ASSERT_EQ(sqlite3_open_v2(shards.back().c_str(), &h, SQLITE_OPEN_READWRITE, nullptr), SQLITE_OK);
      sqlite3_stmt* st = nullptr;
      int done = -1, assigned = -1;
      if (sqlite3_prepare_v2(h, count_sql.c_str(), -1, &st, nullptr) == SQLITE_OK && sqlite3_step(st) == SQLITE_ROW) {
        done = sqlite3_column_int(st, 0);
      }
      sqlite3_finalize(st);
      if (sqlite3_prepare_v2(h, "SELECT COUNT(*) FROM madsfm_shard_pairs", -1, &st, nullptr) == SQLITE_OK &&
          sqlite3_step(st) == SQLITE_ROW) {
        assigned = sqlite3_column_int(st, 0);
      }
      sqlite3_finalize(st);
      sqlite3_close(h);
      // After the read-write open above rolled a hot journal back (a kill inside a batch).
      EXPECT_EQ(testing::IntegrityCheck(shards.back()), "ok");
      EXPECT_TRUE(done % kBatchSize == 0 || done == assigned) << done << " of " << assigned << " results";
      std::printf("shard %d killed after %d of its %d pairs\n", k, done, assigned);
    }
    // The database itself is never written by a shard task.
    EXPECT_EQ(testing::DumpTable(db, "two_view_geometries"), before);
    // Rerun the task to completion: it resumes its shard file.
    const pid_t rerun = StartCli(db, shard_args);
    ASSERT_GT(rerun, 0);
    const int rerun_status = WaitFor(rerun);
    EXPECT_TRUE(WIFEXITED(rerun_status) && WEXITSTATUS(rerun_status) == 0) << "see " << db << ".log";
  }
  EXPECT_GE(num_killed, 1);
  const std::string merge = std::string(MADSFM_CLI_PATH) + " merge_shards --database_path " + db + " " + shards[0] +
                            " " + shards[1] + " > " + db + ".merge.log 2>&1";
  ASSERT_EQ(std::system(merge.c_str()), 0) << "see " << db << ".merge.log";
  for (const char* table : {"two_view_geometries", "matches", "madsfm_two_view_geometries",
                            "madsfm_backup_two_view_geometries"}) {
    EXPECT_EQ(FirstDifference(testing::DumpTable(db, table), testing::DumpTable(ref, table)), "") << table;
  }
  EXPECT_EQ(testing::IntegrityCheck(db), "ok");
}

TEST(TwoViewEstimatorKill, KilledRunsLeaveWholeBatchesAndResumeToTheReferenceResult) {
  const auto t_test = Clock::now();
  const KillProject& p = Project();
  const std::map<int64_t, std::string> original_geometries = RowsByPair(p.original_db, "two_view_geometries");
  const std::map<int64_t, std::string> original_matches = RowsByPair(p.original_db, "matches");
  ASSERT_EQ(original_matches.size(), static_cast<size_t>(kNumPairs));
  ASSERT_EQ(original_geometries.size(), static_cast<size_t>(kNumPairs - kNumPairs / 3));
  std::vector<int64_t> pair_order;  // the estimator's order: matched pairs sorted by pair id
  for (const auto& [id, row] : original_matches) pair_order.push_back(id);
  const std::string original_tvg_dump = testing::DumpTable(p.original_db, "two_view_geometries");

  // Uninterrupted reference run of the CLI.
  const std::string ref = CopyDatabase("reference");
  const double ref_seconds = RunCliToCompletion(ref);
  ASSERT_EQ(testing::IntegrityCheck(ref), "ok");
  const std::map<int64_t, std::string> ref_geometries = RowsByPair(ref, "two_view_geometries");
  const std::map<int64_t, std::string> ref_madsfm = RowsByPair(ref, "madsfm_two_view_geometries");
  const std::map<int64_t, std::pair<int, int>> ref_status = MadsfmStatus(ref);
  ASSERT_EQ(ref_madsfm.size(), static_cast<size_t>(kNumPairs));
  int ref_failed = 0;
  for (const auto& [id, s] : ref_status) ref_failed += s.first != 0;
  const std::string ref_dump_tvg = testing::DumpTable(ref, "two_view_geometries");
  const std::string ref_dump_matches = testing::DumpTable(ref, "matches");
  const std::string ref_dump_madsfm = testing::DumpTable(ref, "madsfm_two_view_geometries");
  const std::string ref_dump_backup = testing::DumpTable(ref, "madsfm_backup_two_view_geometries");
  EXPECT_EQ(FirstDifference(ref_dump_backup, original_tvg_dump), "");
  std::printf("reference CLI run: %d pairs (%d failed, COLMAP's row kept) in %.2f s\n", kNumPairs, ref_failed,
              ref_seconds);

  // One database, run in batches of 16 and killed five times, each run resuming where the last kill left it (so the
  // whole test costs about two runs, which matters under the sanitizers). Kill moments are anchored to the
  // database's progress rather than to a wall time (the machine's load changes): kill k waits until batch b_k of the
  // pair order is written, b_k drawn uniformly from the k-th fifth of the batches before the last one, then a
  // uniformly random part of one batch's time (measured on this run so far), so the kill lands anywhere in the next
  // batch's estimation or write transaction, or in the start-up of the resumed run. Kill 0 may land before the first
  // batch is written (b_0 = 0: a random part of the first batch's expected time).
  const int num_batches = (kNumPairs + kBatchSize - 1) / kBatchSize;
  std::mt19937 rng(20261123);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const std::string db = CopyDatabase("killed");
  int num_killed_mid_run = 0, num_partial = 0;
  size_t last_done = 0;
  for (int k = 0; k < kNumKills; ++k) {
    const int target = k == 0 ? 0 : static_cast<int>((k + uniform(rng)) * (num_batches - 1) / kNumKills);
    const double within = uniform(rng);
    const int batches_before = static_cast<int>(last_done / kBatchSize);
    int fds[2];
    ASSERT_EQ(::pipe(fds), 0) << std::strerror(errno);
    const auto t_start = Clock::now();
    const pid_t pid = StartForkedEstimator(db, fds[1]);
    ::close(fds[1]);
    ASSERT_GT(pid, 0);
    int reported = 0;
    for (char byte; batches_before + reported < target;) {
      const ssize_t n = ::read(fds[0], &byte, 1);
      if (n == 1) ++reported;
      else if (n == 0 || errno != EINTR) break;  // the child exited (or the pipe failed): no more progress
    }
    const double batch_seconds = reported > 0 ? std::chrono::duration<double>(Clock::now() - t_start).count() / reported
                                              : ref_seconds / num_batches;
    std::this_thread::sleep_for(std::chrono::duration<double>(within * batch_seconds));
    ::kill(pid, SIGKILL);
    const double kill_seconds = std::chrono::duration<double>(Clock::now() - t_start).count();
    const int status = WaitFor(pid);
    ::close(fds[0]);
    const bool killed = WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL;
    num_killed_mid_run += killed;
    const bool hot_journal = fs::exists(db + "-journal") && fs::file_size(db + "-journal") > 0;
    SCOPED_TRACE("kill " + std::to_string(k) + " after batch " + std::to_string(target) + " + " +
                 std::to_string(within) + " of a batch");

    // Opening read-write rolls a hot journal back, as COLMAP's next open would.
    const std::map<int64_t, std::string> geometries = RowsByPair(db, "two_view_geometries");
    const std::map<int64_t, std::string> matches = RowsByPair(db, "matches");
    const std::map<int64_t, std::string> madsfm = RowsByPair(db, "madsfm_two_view_geometries");
    EXPECT_EQ(testing::IntegrityCheck(db), "ok");
    const std::map<int64_t, std::pair<int, int>> done = MadsfmStatus(db);
    const std::map<int64_t, int> geometry_counts = GeometryRowCounts(db);
    num_partial += !done.empty() && done.size() < static_cast<size_t>(kNumPairs);
    std::printf("kill %d after batch %d of %d + %.0f%% of a batch (%.2f s after the restart at %zu pairs done): %s, "
                "hot journal %s, %zu/%d pairs done\n",
                k, target, num_batches, 100 * within, kill_seconds, last_done,
                killed ? "SIGKILLed" : "had already exited", hot_journal ? "yes" : "no", done.size(), kNumPairs);
    // What a run committed stays: no kill takes batches away.
    EXPECT_GE(done.size(), last_done);
    last_done = done.size();

    // Whole batches only: the done pairs are the first k * batch_size pairs of the estimator's order.
    EXPECT_TRUE(done.size() % kBatchSize == 0 || done.size() == static_cast<size_t>(kNumPairs)) << done.size();
    // Violations per kind, with the first offending pair (rows are long hex strings: not printed).
    std::map<std::string, std::pair<int, std::string>> violations;
    auto check = [&](bool ok, const std::string& kind, int64_t id, size_t index) {
      if (ok) return;
      auto& v = violations[kind];
      if (v.first++ == 0) v.second = "pair " + std::to_string(id) + " (#" + std::to_string(index) + ")";
    };
    for (size_t i = 0; i < pair_order.size(); ++i) {
      const int64_t id = pair_order[i];
      const bool is_done = done.count(id) != 0;
      check(is_done == (i < done.size()), "done pairs are not a prefix of the pair order", id, i);
      // COLMAP's matches are never touched.
      check(Find(matches, id) == Find(original_matches, id), "matches row changed", id, i);
      if (is_done) {
        // A done pair has its final rows: madsfm's row, and the estimate (or COLMAP's row kept when it failed).
        check(Find(madsfm, id) == Find(ref_madsfm, id), "done: madsfm row differs from the reference", id, i);
        check(Find(geometries, id) == Find(ref_geometries, id), "done: two_view_geometries row differs from the "
              "reference", id, i);
        if (done.at(id).first == 0) {
          const auto count = geometry_counts.find(id);
          check(count != geometry_counts.end() && count->second == done.at(id).second,
                "done (ok): no two_view_geometries row with num_inliers_sampson inliers", id, i);
        } else {
          check(Find(geometries, id) == Find(original_geometries, id), "done (failed): COLMAP's row not kept", id, i);
        }
      } else {
        check(Find(geometries, id) == Find(original_geometries, id), "pending: COLMAP's row changed", id, i);
      }
    }
    for (const auto& [kind, v] : violations) ADD_FAILURE() << kind << ": " << v.first << " pairs, first " << v.second;
    // No other two_view_geometries rows: COLMAP's, plus one per successful done pair that had none.
    size_t expected_geometries = original_geometries.size();
    for (const auto& [id, s] : done) expected_geometries += s.first == 0 && !original_geometries.count(id);
    EXPECT_EQ(geometries.size(), expected_geometries);
    // The backup, when it exists, holds COLMAP's original rows.
    const std::string backup = testing::DumpTable(db, "madsfm_backup_two_view_geometries");
    if (backup != "no table madsfm_backup_two_view_geometries") {
      EXPECT_EQ(FirstDifference(backup, original_tvg_dump), "");
    }
  }
  // Kills hit running processes (anchored to progress, each lands before the last batch unless a batch takes far
  // longer than the ones before it), and some mid-way through the batches.
  EXPECT_GE(num_killed_mid_run, kNumKills - 1);
  EXPECT_GE(num_partial, 1);

  // Resume with the CLI (its own batch size) to completion: byte-identical to the reference run.
  RunCliToCompletion(db);
  EXPECT_EQ(testing::IntegrityCheck(db), "ok");
  EXPECT_EQ(FirstDifference(testing::DumpTable(db, "two_view_geometries"), ref_dump_tvg), "");
  EXPECT_EQ(FirstDifference(testing::DumpTable(db, "matches"), ref_dump_matches), "");
  EXPECT_EQ(FirstDifference(testing::DumpTable(db, "madsfm_two_view_geometries"), ref_dump_madsfm), "");
  EXPECT_EQ(FirstDifference(testing::DumpTable(db, "madsfm_backup_two_view_geometries"), ref_dump_backup), "");

  // `madsfm restore` after a killed-and-resumed run gives COLMAP's original rows back.
  const std::string restore_cmd = std::string(MADSFM_CLI_PATH) + " restore --database_path " + db + " > /dev/null";
  ASSERT_EQ(std::system(restore_cmd.c_str()), 0);
  EXPECT_EQ(FirstDifference(testing::DumpTable(db, "two_view_geometries"), original_tvg_dump), "");
  EXPECT_EQ(testing::IntegrityCheck(db), "ok");
  std::printf("kill test: %d/%d kills mid-run, %d with some batches written, total %.1f s\n", num_killed_mid_run,
              kNumKills, num_partial,
              std::chrono::duration<double>(Clock::now() - t_test).count());
}

}  // namespace
}  // namespace madsfm
