// Bad input to the real `madsfm` CLI (docs/robustness.md): every error exits 1 with a message naming the file /
// pair / camera / option and leaves the database unchanged; documented fallbacks (point-only for images without
// usable depth, skipped pairs) are counted in the summary line.
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "colmap_ext/database/database.h"
#include "madsfm/io/depth_map_io.h"
#include "madsfm/io/npy.h"
#include "madsfm/synthetic/two_view_scene.h"
#include "colmap_ext/synthetic/synthetic_project.h"
#include "testing/colmap_database_builder.h"
#include "testing/temp_dir.h"

namespace madsfm {
namespace {

namespace fs = std::filesystem;

struct CliRun {
  int status;
  std::string out;  // stdout and stderr
};

CliRun RunCli(const std::string& args) {
  const std::string cmd = std::string(MADSFM_CLI_PATH) + " " + args + " 2>&1";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(cmd.c_str(), "r"), pclose);
  std::string out;
  std::array<char, 4096> buf;
  while (fgets(buf.data(), buf.size(), pipe.get())) out += buf.data();
  const int status = pclose(pipe.release());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status), out};
}

bool Contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// The whole database as text, per table: the schema ("sqlite_master") and every table's rows (blobs as hex).
using Snapshot = std::map<std::string, std::string>;

Snapshot TakeSnapshot(const std::string& path) {
  std::vector<std::string> tables;
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
    sqlite3_close(db);
    return {{"error", "cannot open"}};
  }
  sqlite3_stmt* st = nullptr;
  if (sqlite3_prepare_v2(db, "SELECT name FROM sqlite_master WHERE type = 'table' ORDER BY name", -1, &st, nullptr) ==
      SQLITE_OK) {
    while (sqlite3_step(st) == SQLITE_ROW) {
      tables.emplace_back(reinterpret_cast<const char*>(sqlite3_column_text(st, 0)));
    }
  }
  sqlite3_finalize(st);
  sqlite3_close(db);
  Snapshot out;
  out["sqlite_master"] = testing::DumpTable(path, "sqlite_master");
  for (const std::string& t : tables) out[t] = testing::DumpTable(path, t);
  return out;
}

// The tables that differ (added, removed or changed), "" when none.
std::string ChangedTables(const Snapshot& before, const Snapshot& after, bool madsfm_tables) {
  std::string changed;
  auto consider = [&](const std::string& name) {
    const bool ours = name.rfind("madsfm_", 0) == 0 || name == "sqlite_master";
    if (ours != madsfm_tables) return;
    const auto a = before.find(name), b = after.find(name);
    if (a == before.end()) changed += " " + name + " (added)";
    else if (b == after.end()) changed += " " + name + " (removed)";
    else if (a->second != b->second) changed += " " + name + " (changed)";
  };
  for (const auto& [name, rows] : after) consider(name);
  for (const auto& [name, rows] : before) {
    if (!after.count(name)) consider(name);
  }
  return changed;
}

// COLMAP's tables must be untouched; madsfm's own tables (and the schema) should be too. Returns the known-bug
// message when only the latter changed.
std::string ExpectUnchanged(const Snapshot& before, const std::string& path) {
  const Snapshot after = TakeSnapshot(path);
  const std::string colmap_changes = ChangedTables(before, after, false);
  EXPECT_EQ(colmap_changes, "") << "COLMAP tables changed in " << path;
  EXPECT_EQ(testing::IntegrityCheck(path), "ok");
  const std::string ours = ChangedTables(before, after, true);
  return ours.empty() ? "" : "known bug: the rejected run still changed the database:" + ours;
}

std::string FileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A synthetic COLMAP project (colmap_ext/synthetic) of `num_pairs` pairs (images 2k+1, 2k+2 = pair<k>_a.png,
// pair<k>_b.png), one calibrated SIMPLE_PINHOLE camera per pair, 200 matches with 20% outliers, and depth sidecars
// <name>.npy in depths/.
struct Project {
  std::shared_ptr<testing::TempDir> scratch;  // removed with the last copy of the project
  std::string dir, db, depths;
  std::vector<SyntheticPair> pairs;
  std::string Args() const { return "--database_path " + db + " --depth_path " + depths + " --num_threads 2"; }
  std::string Sidecar(int k, char view) const {
    return depths + "/pair" + std::to_string(k) + "_" + std::string(1, view) + ".png.npy";
  }
};

Project MakeProject(const std::string& name, int num_pairs) {
  Project p;
  p.scratch = std::make_shared<testing::TempDir>("robust_" + name);
  p.dir = p.scratch->Sub("project");
  colmap::SyntheticProjectOptions o;
  o.output_path = p.dir;
  o.preset = "indoor_shared_focal";
  o.num_pairs = num_pairs;
  o.min_num_matches = o.max_num_matches = 200;
  o.outlier_ratio = 0.2;
  o.calibrated = true;
  o.seed = 11;
  o.keep_pairs = true;
  colmap::SyntheticProject sp = colmap::WriteSyntheticProject(o);
  p.db = sp.database_path;
  p.depths = sp.depth_path;
  p.pairs = std::move(sp.pairs);
  return p;
}

// A depth map of the pair's image size filled with one value.
void WriteConstantDepth(const Project& p, int k, char view, float value) {
  const PairData& d = p.pairs[k].pair;
  DepthMap m;
  m.width = d.width0;
  m.height = d.height0;
  m.data.assign(static_cast<size_t>(m.width) * m.height, value);
  WriteDepthMapNpy(m, p.Sidecar(k, view));
}

std::string PairIdText(uint32_t a, uint32_t b) { return std::to_string(colmap::ImagePairToPairId(a, b)); }

// Little-endian hex of uint32 values, for SQL blob literals.
std::string HexU32(const std::vector<uint32_t>& v) {
  std::string s;
  char buf[3];
  for (uint32_t x : v) {
    for (int i = 0; i < 4; ++i) {
      std::snprintf(buf, sizeof(buf), "%02x", (x >> (8 * i)) & 0xff);
      s += buf;
    }
  }
  return s;
}

// Runs two_view_estimator on a project expected to be rejected: exit 1, every fragment in the output, database
// unchanged. Returns the known-bug message when only madsfm's own tables changed ("" otherwise).
std::string ExpectRejected(const Project& p, const std::vector<std::string>& fragments, const std::string& extra = "") {
  const Snapshot before = TakeSnapshot(p.db);
  const CliRun r = RunCli("two_view_estimator " + p.Args() + extra);
  EXPECT_EQ(r.status, 1) << r.out;
  for (const std::string& f : fragments) EXPECT_TRUE(Contains(r.out, f)) << "missing '" << f << "' in: " << r.out;
  return ExpectUnchanged(before, p.db);
}

// ---------------------------------------------------------------------------------------------------------------
// Depth files

TEST(Robustness, BadDepthFilesNameTheFileAndLeaveTheDatabaseUnchanged) {
  struct Case {
    std::string name;
    std::function<void(const Project&)> make;
    std::string fragment;
  };
  const std::vector<Case> cases = {
      {"aspect",
       [](const Project& p) {
         const PairData& d = p.pairs[0].pair;
         DepthMap m;  // transposed: height x width
         m.width = d.height0;
         m.height = d.width0;
         m.data.assign(static_cast<size_t>(m.width) * m.height, 2.0f);
         WriteDepthMapNpy(m, p.Sidecar(0, 'a'));
       },
       "aspect ratio"},
      {"three_d",
       [](const Project& p) {
         const std::vector<double> v(3 * 4 * 5, 1.0);
         WriteNpy(p.Sidecar(0, 'a'), {3, 4, 5}, v.data());
       },
       "expected a 2-D array"},
      {"empty",
       [](const Project& p) {
         const std::vector<double> v;
         WriteNpy(p.Sidecar(0, 'a'), {0, 5}, v.data());
       },
       "empty depth map"},
      {"truncated",
       [](const Project& p) {
         const std::string bytes = FileBytes(p.Sidecar(0, 'a'));
         std::ofstream(p.Sidecar(0, 'a'), std::ios::binary) << bytes.substr(0, bytes.size() / 2);
       },
       "truncated data"},
      {"int_dtype",
       [](const Project& p) {
         // A valid .npy header of int32 with matching data size.
         const PairData& d = p.pairs[0].pair;
         std::string header = "{'descr': '<i4', 'fortran_order': False, 'shape': (" + std::to_string(d.height0) +
                              ", " + std::to_string(d.width0) + "), }";
         while ((10 + header.size() + 1) % 64 != 0) header += ' ';
         header += '\n';
         std::string bytes = "\x93NUMPY";
         bytes += '\x01';
         bytes += '\x00';
         bytes += static_cast<char>(header.size() & 0xff);
         bytes += static_cast<char>(header.size() >> 8);
         bytes += header;
         bytes += std::string(static_cast<size_t>(d.width0) * d.height0 * 4, '\x01');
         std::ofstream(p.Sidecar(0, 'a'), std::ios::binary) << bytes;
       },
       "expected a float16/float32/float64 array"},
  };
  std::string bug;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const Project p = MakeProject("depth_" + c.name, 2);
    c.make(p);
    const std::string b = ExpectRejected(p, {"pair0_a.png.npy", c.fragment});
    if (!b.empty()) bug = b + " (" + c.name + ")";
  }
  if (!bug.empty()) ADD_FAILURE() << bug;
}

TEST(Robustness, DepthWithoutValidValuesFallsBackToPointsAndIsCounted) {
  // One image of each of pairs 0..3 has a depth map that is all NaN, all zero, all negative, all +inf; pair 4 is
  // intact. The first four are estimated point-only; the summary counts them.
  const Project p = MakeProject("invalid_depth", 5);
  WriteConstantDepth(p, 0, 'a', std::numeric_limits<float>::quiet_NaN());
  WriteConstantDepth(p, 1, 'b', 0.0f);
  WriteConstantDepth(p, 2, 'a', -3.0f);
  WriteConstantDepth(p, 3, 'b', std::numeric_limits<float>::infinity());
  const CliRun r = RunCli("two_view_estimator " + p.Args());
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_TRUE(Contains(r.out, "5 matched pairs: 5 estimated (4 point-only for lack of depth)")) << r.out;
  auto db = colmap::Database::Open(p.db, true);
  for (int k = 0; k < 5; ++k) {
    const auto row = db->ReadMadsfmPair(colmap::ImagePairToPairId(2 * k + 1, 2 * k + 2));
    ASSERT_TRUE(row.has_value()) << k;
    EXPECT_EQ(row->method, k < 4 ? 1 : 0) << "pair " << k << " (method 1 = point-only)";
  }
}

TEST(Robustness, MissingSidecarsFallBackToPointsAndAreCounted) {
  const Project p = MakeProject("missing_sidecar", 3);
  fs::remove(p.Sidecar(0, 'a'));
  fs::remove(p.Sidecar(1, 'b'));
  const CliRun r = RunCli("two_view_estimator " + p.Args());
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_TRUE(Contains(r.out, "3 matched pairs: 3 estimated (2 point-only for lack of depth)")) << r.out;
  EXPECT_TRUE(Contains(r.out, "6 images, 4 with depth")) << r.out;
}

TEST(Robustness, NonexistentDepthFolderIsAnError) {
  // A mistyped --depth_path must not silently turn every pair into a point-only estimate.
  const Project p = MakeProject("no_depth_folder", 1);
  const Snapshot before = TakeSnapshot(p.db);
  const CliRun r = RunCli("two_view_estimator --database_path " + p.db + " --depth_path " + p.dir + "/typo_depths");
  if (r.status == 0) {
    FAIL() << "regression: a --depth_path folder that does not exist is accepted silently (every image "
              "point-only); output: "
           << r.out;
  }
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_TRUE(Contains(r.out, "typo_depths")) << r.out;
  const std::string bug = ExpectUnchanged(before, p.db);
  if (!bug.empty()) ADD_FAILURE() << bug;
}

// ---------------------------------------------------------------------------------------------------------------
// Databases

TEST(Robustness, DatabaseThatIsATextFile) {
  const Project p = MakeProject("text_db", 1);
  const std::string text = p.dir + "/notes.db";
  std::ofstream(text) << "this is a text file, long enough to fill a database header........\n";
  const std::string bytes = FileBytes(text);
  const CliRun r = RunCli("two_view_estimator --database_path " + text + " --depth_path " + p.depths);
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_TRUE(Contains(r.out, "'" + text + "' is not a SQLite database")) << r.out;
  EXPECT_EQ(FileBytes(text), bytes);
}

TEST(Robustness, DatabaseWithAnUnknownSchema) {
  const Project p = MakeProject("schema_db", 1);
  const std::string other = p.dir + "/other.db";
  {
    sqlite3* raw = nullptr;
    ASSERT_EQ(sqlite3_open(other.c_str(), &raw), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(raw, "CREATE TABLE cameras (x INTEGER); CREATE TABLE foo (y TEXT)", nullptr, nullptr,
                           nullptr),
              SQLITE_OK);
    sqlite3_close(raw);
  }
  const Snapshot before = TakeSnapshot(other);
  const CliRun r = RunCli("two_view_estimator --database_path " + other);
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_TRUE(Contains(r.out, "other.db")) << r.out;
  EXPECT_TRUE(Contains(r.out, "unknown schema")) << r.out;
  const Snapshot after = TakeSnapshot(other);
  EXPECT_EQ(ChangedTables(before, after, false) + ChangedTables(before, after, true), "");
}

TEST(Robustness, MissingDatabaseIsNotCreated) {
  const Project p = MakeProject("missing_db", 1);
  const std::string missing = p.dir + "/missing.db";
  const CliRun r = RunCli("two_view_estimator --database_path " + missing);
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_TRUE(Contains(r.out, "'" + missing + "' does not exist")) << r.out;
  EXPECT_FALSE(fs::exists(missing));
}

TEST(Robustness, DatabaseLockedByAnotherWriter) {
  const Project p = MakeProject("locked_db", 2);
  const Snapshot before = TakeSnapshot(p.db);
  sqlite3* other = nullptr;
  ASSERT_EQ(sqlite3_open(p.db.c_str(), &other), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(other, "BEGIN EXCLUSIVE", nullptr, nullptr, nullptr), SQLITE_OK);
  const auto start = std::chrono::steady_clock::now();
  const CliRun r = RunCli("two_view_estimator " + p.Args());
  const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  sqlite3_exec(other, "ROLLBACK", nullptr, nullptr, nullptr);
  sqlite3_close(other);
  std::printf("locked database: exit %d after %.1f s: %s", r.status, waited, r.out.c_str());
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_TRUE(Contains(r.out, p.db)) << r.out;
  EXPECT_TRUE(Contains(r.out, "locked")) << r.out;
  EXPECT_GE(waited, 4.0) << "the CLI waits for the busy timeout (5 s) before giving up";
  const std::string bug = ExpectUnchanged(before, p.db);
  // Once the other writer is gone the same command works.
  EXPECT_EQ(RunCli("two_view_estimator " + p.Args()).status, 0);
  if (!bug.empty()) ADD_FAILURE() << bug;
}

TEST(Robustness, ReadOnlyDatabaseFile) {
  const Project p = MakeProject("readonly_db", 1);
  const std::string bytes = FileBytes(p.db);
  ASSERT_EQ(::chmod(p.db.c_str(), 0444), 0);
  for (const std::string& cmd : {"two_view_estimator " + p.Args(), "focal_estimator --database_path " + p.db,
                                "restore --database_path " + p.db}) {
    const CliRun r = RunCli(cmd);
    EXPECT_EQ(r.status, 1) << cmd << ": " << r.out;
    EXPECT_TRUE(Contains(r.out, "'" + p.db + "' is a read-only file")) << cmd << ": " << r.out;
  }
  EXPECT_EQ(FileBytes(p.db), bytes);
  ::chmod(p.db.c_str(), 0644);
}

TEST(Robustness, KeypointBlobSizeMismatchNamesTheImage) {
  const Project p = MakeProject("kp_blob", 2);
  testing::ExecSql(p.db, "UPDATE keypoints SET rows = rows + 1 WHERE image_id = 3");
  const std::string bug = ExpectRejected(p, {p.db, "keypoints of 'pair1_a.png' (image_id 3): blob has", "bytes"});
  if (!bug.empty()) ADD_FAILURE() << bug;
}

TEST(Robustness, MatchesPointingPastTheKeypointsNameThePair) {
  const Project p = MakeProject("past_keypoints", 2);
  // Pair (3, 4): 20 good matches and one pointing at keypoint 9999 of image 3.
  std::vector<uint32_t> data;
  for (uint32_t i = 0; i < 20; ++i) data.insert(data.end(), {i, i});
  data.insert(data.end(), {9999, 0});
  testing::ExecSql(p.db, "UPDATE matches SET rows = 21, data = x'" + HexU32(data) + "' WHERE pair_id = " +
                             PairIdText(3, 4));
  const std::string bug =
      ExpectRejected(p, {p.db, "pair " + PairIdText(3, 4) + " ('pair1_a.png' (image_id 3), 'pair1_b.png' (image_id 4))",
                         "point past the keypoints", "9999"});
  if (!bug.empty()) ADD_FAILURE() << bug;
}

TEST(Robustness, MatchesBlobSizeMismatchNamesThePair) {
  const Project p = MakeProject("matches_blob", 2);
  testing::ExecSql(p.db, "UPDATE matches SET rows = rows + 1 WHERE pair_id = " + PairIdText(1, 2));
  const std::string bug = ExpectRejected(p, {p.db, "('pair0_a.png' (image_id 1), 'pair0_b.png' (image_id 2))"});
  if (!bug.empty()) ADD_FAILURE() << bug;
}

TEST(Robustness, UnsupportedCameraModelNamesTheCamera) {
  const Project p = MakeProject("fov_camera", 2);
  // FOV (id 7, 5 params).
  testing::ExecSql(p.db, "UPDATE cameras SET model = 7, params = x'" + std::string(80, '0') + "' WHERE camera_id = 2");
  const std::string bug = ExpectRejected(p, {p.db, "camera_id 2 (used by 'pair1_a.png', 'pair1_b.png')", "FOV"});
  if (!bug.empty()) ADD_FAILURE() << bug;
}

TEST(Robustness, PairsWithZeroOrFewMatchesAreSkipped) {
  const Project p = MakeProject("few_matches", 2);
  // Pair (1, 3): a row with 0 matches (COLMAP's matchers write those); pair (2, 4): 5 matches.
  testing::ExecSql(p.db, "INSERT INTO matches(pair_id, rows, cols, data) VALUES(" + PairIdText(1, 3) + ", 0, 2, x'')");
  std::vector<uint32_t> five;
  for (uint32_t i = 0; i < 5; ++i) five.insert(five.end(), {i, i});
  testing::ExecSql(p.db, "INSERT INTO matches(pair_id, rows, cols, data) VALUES(" + PairIdText(2, 4) + ", 5, 2, x'" +
                             HexU32(five) + "')");
  const CliRun r = RunCli("two_view_estimator " + p.Args());
  ASSERT_EQ(r.status, 0) << r.out;
  // The 0-match row is not a matched pair at all; the 5-match pair is counted as skipped.
  EXPECT_TRUE(Contains(r.out, "3 matched pairs: 2 estimated")) << r.out;
  EXPECT_TRUE(Contains(r.out, "1 with < 15 matches")) << r.out;
  auto db = colmap::Database::Open(p.db, true);
  EXPECT_FALSE(db->ReadTwoViewGeometry(colmap::ImagePairToPairId(1, 3)).has_value());
  EXPECT_FALSE(db->ReadTwoViewGeometry(colmap::ImagePairToPairId(2, 4)).has_value());
  EXPECT_FALSE(db->ReadMadsfmPair(colmap::ImagePairToPairId(2, 4)).has_value());
}

TEST(Robustness, LaterStepsBeforeTwoViewEstimator) {
  // seed_model on a database two_view_estimator never processed: a clear error, no model, database unchanged;
  // focal_estimator and restore have nothing to do and change nothing.
  const Project p = MakeProject("no_estimates", 1);
  const Snapshot before = TakeSnapshot(p.db);
  CliRun r = RunCli("seed_model --database_path " + p.db + " --output_path " + p.dir + "/seed");
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_TRUE(Contains(r.out, "database '" + p.db + "': no pair estimated by two_view_estimator")) << r.out;
  EXPECT_TRUE(Contains(r.out, "run two_view_estimator first")) << r.out;
  EXPECT_FALSE(fs::exists(p.dir + "/seed/images.bin"));
  r = RunCli("focal_estimator --database_path " + p.db);
  EXPECT_EQ(r.status, 0) << r.out;
  r = RunCli("restore --database_path " + p.db);
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_TRUE(Contains(r.out, "restore: 0 two-view geometries restored")) << r.out;
  const Snapshot after = TakeSnapshot(p.db);
  EXPECT_EQ(ChangedTables(before, after, false) + ChangedTables(before, after, true), "");
}

TEST(Robustness, MissingPairListNamesTheFile) {
  const Project p = MakeProject("pair_list", 1);
  const std::string list = p.dir + "/nope.txt";
  const std::string bug = ExpectRejected(p, {"cannot read pair list '" + list + "'"}, " --pair_list " + list);
  if (!bug.empty()) ADD_FAILURE() << bug;
}

// ---------------------------------------------------------------------------------------------------------------
// Command-line options

// `synth_project --colmap_version` writes that release's schema; an unknown release names the option and the known
// ones and writes nothing.
TEST(Robustness, SynthProjectColmapVersion) {
  const testing::TempDir scratch("robust_synth_version");
  const std::string dir = scratch.Sub("project");
  CliRun r = RunCli("synth_project --output_path " + dir + " --num_pairs 2 --colmap_version 4.0");
  ASSERT_EQ(r.status, 0) << r.out;
  auto db = colmap::Database::Open(dir + "/database.db", true);
  EXPECT_EQ(db->user_version(), 4000400);
  EXPECT_EQ(db->schema(), colmap::SchemaVersion::kColmap4);
  EXPECT_EQ(db->ReadImages().size(), 4u);
  db.reset();
  fs::remove_all(dir);
  r = RunCli("synth_project --output_path " + dir + " --num_pairs 2 --colmap_version 5.0");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(Contains(r.out, "unknown --colmap_version '5.0' (known: 3.8, 3.9, 3.10, 3.11, 3.12, 3.13, 4.0, 4.1, "
                              "main)"))
      << r.out;
  EXPECT_FALSE(fs::exists(dir + "/database.db"));
}

TEST(Robustness, CommandLineErrorsAreClearAndExit1) {
  struct Command {
    std::string name, good_args, int_option, required;
  };
  const std::vector<Command> commands = {
      {"two_view_estimator", "--database_path /tmp/x.db", "num_threads", "database_path"},
      {"focal_estimator", "--database_path /tmp/x.db", "min_num_pairs", "database_path"},
      {"seed_model", "--database_path /tmp/x.db --output_path /tmp/x", "min_num_inliers", "output_path"},
      {"mapper", "--database_path /tmp/x.db --image_path /tmp --output_path /tmp/x", "num_threads", "image_path"},
  };
  for (const Command& c : commands) {
    SCOPED_TRACE(c.name);
    CliRun r = RunCli(c.name + " " + c.good_args + " --bogus 1");
    EXPECT_EQ(r.status, 1);
    EXPECT_TRUE(Contains(r.out, "madsfm " + c.name + ": unknown option --bogus")) << r.out;
    r = RunCli(c.name + " " + c.good_args + " --" + c.int_option + " abc");
    EXPECT_EQ(r.status, 1);
    EXPECT_TRUE(Contains(r.out, "bad value 'abc' for --" + c.int_option + " (expected INT)")) << r.out;
    r = RunCli(c.name + " " + c.good_args + " --" + c.int_option);
    EXPECT_EQ(r.status, 1);
    EXPECT_TRUE(Contains(r.out, "option --" + c.int_option + " needs a value")) << r.out;
    r = RunCli(c.name);
    EXPECT_EQ(r.status, 1);
    EXPECT_TRUE(Contains(r.out, "missing required option --database_path")) << r.out;
    std::string without = c.good_args;
    const size_t at = without.find("--" + c.required);
    without.erase(at, without.find(' ', at + c.required.size() + 3) - at);
    r = RunCli(c.name + " " + without);
    EXPECT_EQ(r.status, 1);
    EXPECT_TRUE(Contains(r.out, "missing required option --" + c.required)) << r.out;
    r = RunCli(c.name + " " + c.good_args + " stray");
    EXPECT_EQ(r.status, 1);
    EXPECT_TRUE(Contains(r.out, "unexpected argument 'stray'")) << r.out;
  }
  const CliRun r = RunCli("no_such_command");
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(Contains(r.out, "unknown command 'no_such_command'")) << r.out;
}

TEST(Robustness, BadOptionValuesCheckedAfterParsingLeaveTheDatabaseUnchanged) {
  const Project p = MakeProject("bad_values", 1);
  std::string bug = ExpectRejected(p, {"fisheye"}, " --camera_mode fisheye");
  bug += ExpectRejected(p, {"unknown depth type 'inverse'"}, " --depth_type inverse");
  bug += ExpectRejected(p, {"bad value 'nan' for --reproj_threshold"}, " --reproj_threshold nan");
  if (!bug.empty()) ADD_FAILURE() << bug;
}

TEST(Robustness, MapperWithoutColmapNamesTheExecutable) {
  const Project p = MakeProject("mapper_colmap", 1);
  const Snapshot before = TakeSnapshot(p.db);
  const CliRun r = RunCli("mapper --database_path " + p.db + " --image_path " + p.dir + " --output_path " + p.dir +
                          "/out --colmap_path /nonexistent/colmap");
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_TRUE(Contains(r.out, "colmap executable '/nonexistent/colmap' not found")) << r.out;
  EXPECT_FALSE(fs::exists(p.dir + "/out"));
  const std::string bug = ExpectUnchanged(before, p.db);
  if (!bug.empty()) ADD_FAILURE() << bug;
}

}  // namespace
}  // namespace madsfm
