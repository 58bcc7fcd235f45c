// `madsfm pair` as a user runs it: JSON on success, clear errors naming the file on bad pair directories.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "madsfm/io/npy.h"

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

std::string CopyPair(const std::string& name) {
  const fs::path dst = fs::temp_directory_path() / ("madsfm_pair_cli_" + name);
  fs::remove_all(dst);
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

TEST(PairCommand, BadPairDirectoriesGiveClearErrors) {
  {
    const CliRun r = RunCli("pair --pair_path /nonexistent/pair");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.out.find("/nonexistent/pair"), std::string::npos) << r.out;
  }
  {  // missing matches file
    const std::string dir = CopyPair("missing");
    fs::remove(fs::path(dir) / "lightglue_matches_1.npy");
    const CliRun r = RunCli("pair --pair_path " + dir);
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.out.find("lightglue_matches_1.npy"), std::string::npos) << r.out;
  }
  {  // wrong shape
    const std::string dir = CopyPair("shape");
    const std::vector<double> v(30, 1.0);
    madsfm::WriteNpy((fs::path(dir) / "lightglue_matches_0.npy").string(), {10, 3}, v.data());
    const CliRun r = RunCli("pair --pair_path " + dir);
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.out.find("lightglue_matches_0.npy"), std::string::npos) << r.out;
  }
  {  // 0 matches
    const std::string dir = CopyPair("empty");
    const std::vector<double> v;
    madsfm::WriteNpy((fs::path(dir) / "lightglue_matches_0.npy").string(), {0, 2}, v.data());
    madsfm::WriteNpy((fs::path(dir) / "lightglue_matches_1.npy").string(), {0, 2}, v.data());
    const CliRun r = RunCli("pair --pair_path " + dir);
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.out.find("0 matches"), std::string::npos) << r.out;
  }
  {  // NaN depth is not an error: those matches have no depth
    const std::string dir = CopyPair("nan");
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
