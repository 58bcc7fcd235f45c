// `madsfm pair` as a user runs it: JSON on success, clear errors naming the file on bad pair directories.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "madsfm/io/npy.h"
#include "testing/temp_dir.h"

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
  return {WEXITSTATUS(status), out};
}

// A writable copy of the example pair 1_eth3d inside `scratch`.
std::string CopyPair(const madsfm::testing::TempDir& scratch) {
  const fs::path dst = scratch.Sub("pair");
  fs::copy(fs::path(MADSFM_EXAMPLE_PAIRS_DIR) / "1_eth3d", dst);
  for (const auto& e : fs::directory_iterator(dst)) fs::permissions(e.path(), fs::perms::owner_write, fs::perm_options::add);
  return dst.string();
}

TEST(PairCommand, PrintsTheEstimateAndItsErrorsAsJson) {
  const CliRun r = RunCli("pair --pair_path " + std::string(MADSFM_EXAMPLE_PAIRS_DIR) + "/1_eth3d --camera_mode shared_focal");
  ASSERT_EQ(r.status, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["status"], "ok");
  EXPECT_EQ(j["R"].size(), 9u);
  EXPECT_EQ(j["t"].size(), 3u);
  for (const char* key : {"scale", "shift0", "shift1", "f0", "f1", "iterations", "runtime_ms"}) EXPECT_TRUE(j.contains(key));
  EXPECT_LT(j["rot_err_deg"].get<double>(), 5.0);
  EXPECT_LT(j["focal_err"].get<double>(), 0.1);
  EXPECT_GT(j["inliers"]["sampson"].get<int>(), 100);
  // The depth corrections' uncertainty: finite sigmas, and observable exactly when all are within the default 0.1.
  bool within = true;
  for (const char* key : {"sigma_scale", "sigma_shift0", "sigma_shift1"}) {
    ASSERT_TRUE(j[key].is_number()) << key;
    EXPECT_GE(j[key].get<double>(), 0.0);
    within = within && j[key].get<double>() <= 0.1;
  }
  EXPECT_EQ(j["depth_observable"].get<bool>(), within);
  // Determined corrections: neither replaced by the scale-only search nor reset.
  EXPECT_FALSE(j["shifts_dropped"].get<bool>());
  EXPECT_FALSE(j["scale_reset"].get<bool>());
  ASSERT_TRUE(j["low_parallax_weighting"].is_boolean());
}

TEST(PairCommand, PointMethodReportsNoDepthCorrections) {
  const CliRun r = RunCli("pair --pair_path " + std::string(MADSFM_EXAMPLE_PAIRS_DIR) + "/0_scannet --camera_mode calibrated");
  ASSERT_EQ(r.status, 0) << r.out;
  const size_t start = r.out.find('{');  // after the notes stderr printed (RunCli merges both streams)
  ASSERT_NE(start, std::string::npos) << r.out;
  const auto j = nlohmann::json::parse(r.out.substr(start, r.out.rfind('}') - start + 1));
  EXPECT_FALSE(j["depth_observable"].get<bool>());
  EXPECT_TRUE(j["sigma_scale"].is_null());
}

TEST(PairCommand, PairWithoutDepthRunsThePointMethodAndSaysSo) {
  const CliRun r = RunCli("pair --pair_path " + std::string(MADSFM_EXAMPLE_PAIRS_DIR) + "/0_scannet --camera_mode calibrated");
  EXPECT_NE(r.out.find("point method"), std::string::npos) << r.out;
}

std::vector<std::string> SplitCsvLine(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string item;
  while (std::getline(ss, item, ',')) out.push_back(item);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

// `bench` writes whether each estimate determines its depth corrections, with their standard deviations, and says in
// summary.json how often it did and how good the flagged ones were against the true depths.
TEST(BenchCommand, PerPairCsvCarriesTheDepthFlagAndItsSigmas) {
  const madsfm::testing::TempDir scratch("bench_cli_observable");
  const fs::path dir = scratch.path();
  const CliRun synth = RunCli("synth --preset hard_low_parallax_calibrated --num_pairs 6 --seed 5 --output_path " +
                              (dir / "pairs").string());
  ASSERT_EQ(synth.status, 0) << synth.out;
  const CliRun r = RunCli("bench --pairs_path " + (dir / "pairs").string() + " --method hybrid,points --output_path " +
                          (dir / "out").string());
  ASSERT_EQ(r.status, 0) << r.out;
  std::ifstream csv(dir / "out" / "per_pair.csv");
  std::string line;
  ASSERT_TRUE(std::getline(csv, line));
  const std::vector<std::string> header = SplitCsvLine(line);
  std::map<std::string, size_t> col;
  for (size_t i = 0; i < header.size(); ++i) col[header[i]] = i;
  for (const char* name : {"depth_observable", "sigma_scale", "sigma_shift0", "sigma_shift1", "sigma_focal0",
                           "depth_err", "depth_err_oracle", "shifts_dropped", "scale_reset",
                           "low_parallax_weighting"}) {
    ASSERT_TRUE(col.count(name)) << name;
  }
  int hybrid_measured = 0, hybrid_observable = 0, observable_good = 0, points_rows = 0;
  while (std::getline(csv, line)) {
    const std::vector<std::string> f = SplitCsvLine(line);
    ASSERT_EQ(f.size(), header.size()) << line;
    const std::string method = f[col["method"]];
    const bool observable = f[col["depth_observable"]] == "1";
    ASSERT_TRUE(observable || f[col["depth_observable"]] == "0") << line;
    EXPECT_TRUE(f[col["sigma_focal0"]].empty()) << "calibrated: no focal sigma: " << line;
    if (method == "points") {
      ++points_rows;
      EXPECT_FALSE(observable) << line;
      EXPECT_EQ(f[col["low_parallax_weighting"]], "0") << "no Sampson weight to lower: " << line;
      EXPECT_TRUE(f[col["sigma_scale"]].empty()) << line;
      continue;
    }
    ASSERT_EQ(method, "hybrid");
    ASSERT_TRUE(f[col["shifts_dropped"]] == "0" || f[col["shifts_dropped"]] == "1") << line;
    ASSERT_TRUE(f[col["scale_reset"]] == "0" || f[col["scale_reset"]] == "1") << line;
    ASSERT_TRUE(f[col["low_parallax_weighting"]] == "0" || f[col["low_parallax_weighting"]] == "1") << line;
    if (f[col["shifts_dropped"]] == "1") {
      // Undetermined shifts, replaced by the scale-only search's result: shifts 0, not estimated, not observable.
      EXPECT_FALSE(observable) << line;
      EXPECT_EQ(std::stod(f[col["shift0"]]), 0.0) << line;
      EXPECT_EQ(std::stod(f[col["shift1"]]), 0.0) << line;
      EXPECT_TRUE(f[col["sigma_shift0"]].empty() && f[col["sigma_shift1"]].empty()) << line;
    } else if (f[col["scale_reset"]] == "1") {
      // A scale that drifted without bound: replaced by the priors' ratio, not observable, no scale sigma.
      EXPECT_FALSE(observable) << line;
      EXPECT_TRUE(f[col["sigma_scale"]].empty()) << line;
    } else {
      bool within = true;
      for (const char* name : {"sigma_scale", "sigma_shift0", "sigma_shift1"}) {
        ASSERT_FALSE(f[col[name]].empty()) << name << ": " << line;
        const double sigma = std::stod(f[col[name]]);
        EXPECT_GE(sigma, 0.0);
        within = within && sigma <= 0.1;  // the default --max_depth_sigma
      }
      EXPECT_EQ(observable, within) << line;  // with shifts (hybrid's default) the sigmas decide
    }
    if (f[col["depth_err"]].empty()) continue;
    ++hybrid_measured;
    hybrid_observable += observable;
    observable_good += observable && std::stod(f[col["depth_err"]]) <= 1.25 * std::stod(f[col["depth_err_oracle"]]);
  }
  EXPECT_EQ(points_rows, 6);
  ASSERT_EQ(hybrid_measured, 6);
  std::ifstream js(dir / "out" / "summary.json");
  const auto summary = nlohmann::json::parse(js)["methods"]["hybrid"];
  EXPECT_DOUBLE_EQ(summary["depth_observable_share"].get<double>(), hybrid_observable / 6.0);
  if (hybrid_observable > 0) {
    EXPECT_DOUBLE_EQ(summary["depth_within_1.25x_oracle_observable"].get<double>(),
                     static_cast<double>(observable_good) / hybrid_observable);
  } else {
    EXPECT_FALSE(summary.contains("depth_within_1.25x_oracle_observable"));
  }
}

TEST(PairCommand, BadPairDirectoriesGiveClearErrors) {
  {
    const CliRun r = RunCli("pair --pair_path /nonexistent/pair");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.out.find("/nonexistent/pair"), std::string::npos) << r.out;
  }
  {  // missing matches file
    const madsfm::testing::TempDir scratch("pair_cli_missing");
    const std::string dir = CopyPair(scratch);
    fs::remove(fs::path(dir) / "lightglue_matches_1.npy");
    const CliRun r = RunCli("pair --pair_path " + dir);
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.out.find("lightglue_matches_1.npy"), std::string::npos) << r.out;
  }
  {  // wrong shape
    const madsfm::testing::TempDir scratch("pair_cli_shape");
    const std::string dir = CopyPair(scratch);
    const std::vector<double> v(30, 1.0);
    madsfm::WriteNpy((fs::path(dir) / "lightglue_matches_0.npy").string(), {10, 3}, v.data());
    const CliRun r = RunCli("pair --pair_path " + dir);
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.out.find("lightglue_matches_0.npy"), std::string::npos) << r.out;
  }
  {  // 0 matches
    const madsfm::testing::TempDir scratch("pair_cli_empty");
    const std::string dir = CopyPair(scratch);
    const std::vector<double> v;
    madsfm::WriteNpy((fs::path(dir) / "lightglue_matches_0.npy").string(), {0, 2}, v.data());
    madsfm::WriteNpy((fs::path(dir) / "lightglue_matches_1.npy").string(), {0, 2}, v.data());
    const CliRun r = RunCli("pair --pair_path " + dir);
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.out.find("0 matches"), std::string::npos) << r.out;
  }
  {  // NaN depth is not an error: those matches have no depth
    const madsfm::testing::TempDir scratch("pair_cli_nan");
    const std::string dir = CopyPair(scratch);
    std::vector<double> d(480 * 720, std::nan(""));
    madsfm::WriteNpy((fs::path(dir) / "da-met_depth_0.npy").string(), {480, 720}, d.data());
    const CliRun r = RunCli("pair --pair_path " + dir);
    EXPECT_NE(r.out.find("point method"), std::string::npos) << r.out;
  }
  {  // unknown option and bad value
    EXPECT_NE(RunCli("pair --pair_path x --bogus 1").out.find("unknown option --bogus"), std::string::npos);
    EXPECT_NE(RunCli("pair --pair_path x --seed abc").out.find("bad value 'abc' for --seed"), std::string::npos);
    EXPECT_NE(RunCli("pair --pair_path x --camera_mode fisheye").out.find("fisheye"), std::string::npos);
  }
}

}  // namespace
