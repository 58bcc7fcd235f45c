#include "madsfm/synthetic/two_view_scene.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

namespace madsfm {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Bilinear sample of a map at image point p of a width x height image (docs/design.md section 5).
double SampleMap(const DepthMap& map, const Eigen::Vector2d& p, int width, int height) {
  const double x = std::clamp((p.x() + 0.5) * map.width / width - 0.5, 0.0, map.width - 1.0);
  const double y = std::clamp((p.y() + 0.5) * map.height / height - 0.5, 0.0, map.height - 1.0);
  const int x0 = std::min(static_cast<int>(x), map.width - 2 < 0 ? 0 : map.width - 2);
  const int y0 = std::min(static_cast<int>(y), map.height - 2 < 0 ? 0 : map.height - 2);
  const int x1 = std::min(x0 + 1, map.width - 1), y1 = std::min(y0 + 1, map.height - 1);
  const double ax = x - x0, ay = y - y0;
  return (1 - ay) * ((1 - ax) * map.At(x0, y0) + ax * map.At(x1, y0)) +
         ay * ((1 - ax) * map.At(x0, y1) + ax * map.At(x1, y1));
}

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

Eigen::Matrix3d Fundamental(const SyntheticPair& s) {
  const Eigen::Matrix4d& T = *s.pair.T_0to1;
  const Eigen::Matrix3d E = Skew(T.block<3, 1>(0, 3)) * T.block<3, 3>(0, 0);
  return s.pair.K1.inverse().transpose() * E * s.pair.K0.inverse();
}

// Sampson error in pixels.
double Sampson(const Eigen::Matrix3d& F, const Eigen::Vector2d& p0, const Eigen::Vector2d& p1) {
  const Eigen::Vector3d x0 = p0.homogeneous(), x1 = p1.homogeneous();
  const Eigen::Vector3d Fx0 = F * x0, Ftx1 = F.transpose() * x1;
  const double num = x1.dot(Fx0);
  const double den = Fx0.head<2>().squaredNorm() + Ftx1.head<2>().squaredNorm();
  return den > 0.0 ? std::abs(num) / std::sqrt(den) : 0.0;
}

Eigen::Vector2d Project(const Eigen::Matrix3d& K, const Eigen::Vector3d& X) { return (K * X).hnormalized(); }

void ExpectSamePair(const SyntheticPair& a, const SyntheticPair& b) {
  ASSERT_EQ(a.pair.p0.size(), b.pair.p0.size());
  for (size_t i = 0; i < a.pair.p0.size(); ++i) {
    ASSERT_EQ(a.pair.p0[i], b.pair.p0[i]);
    ASSERT_EQ(a.pair.p1[i], b.pair.p1[i]);
    ASSERT_EQ(a.is_inlier[i], b.is_inlier[i]);
    ASSERT_EQ(a.points0[i], b.points0[i]);
  }
  EXPECT_EQ(a.pair.K0, b.pair.K0);
  EXPECT_EQ(a.pair.K1, b.pair.K1);
  EXPECT_EQ(*a.pair.T_0to1, *b.pair.T_0to1);
  EXPECT_EQ(a.pair.depth0->data, b.pair.depth0->data);
  EXPECT_EQ(a.pair.depth1->data, b.pair.depth1->data);
  EXPECT_EQ(a.true_depth_map0.data, b.true_depth_map0.data);
  EXPECT_EQ(a.wild_mask1, b.wild_mask1);
  EXPECT_EQ(a.prior_scale0, b.prior_scale0);
  EXPECT_EQ(a.prior_shift1, b.prior_shift1);
  EXPECT_EQ(a.pixel_noise, b.pixel_noise);
}

SyntheticPairOptions Preset(const std::string& name) {
  const std::optional<SyntheticPairOptions> o = SyntheticPairPreset(name);
  EXPECT_TRUE(o.has_value()) << name;
  return o.value_or(SyntheticPairOptions());
}

TEST(TwoViewScene, DeterministicForASeed) {
  for (const char* name : {"indoor_calibrated", "outdoor_two_focal", "indoor_bad_prior"}) {
    const SyntheticPairOptions o = Preset(name);
    const SyntheticPair a = GenerateTwoViewPair(o, 12345);
    const SyntheticPair b = GenerateTwoViewPair(o, 12345);
    ExpectSamePair(a, b);
    const SyntheticPair c = GenerateTwoViewPair(o, 12346);
    EXPECT_NE(a.pair.p0[0], c.pair.p0[0]) << name;
    EXPECT_NE(a.pair.depth0->data, c.pair.depth0->data) << name;
    EXPECT_NE(*a.pair.T_0to1, *c.pair.T_0to1) << name;
  }
}

TEST(TwoViewScene, SetIsDeterministicAndPrefixStable) {
  const SyntheticPairOptions o = Preset("indoor_shared_focal");
  const std::vector<SyntheticPair> small = GenerateTwoViewSet(o, 3, 99);
  const std::vector<SyntheticPair> large = GenerateTwoViewSet(o, 5, 99);
  ASSERT_EQ(small.size(), 3u);
  ASSERT_EQ(large.size(), 5u);
  for (int i = 0; i < 3; ++i) ExpectSamePair(small[i], large[i]);
  for (int i = 1; i < 5; ++i) EXPECT_NE(*large[i].pair.T_0to1, *large[0].pair.T_0to1);
  EXPECT_TRUE(GenerateTwoViewSet(o, 0, 99).empty());
}

TEST(TwoViewScene, InliersAreConsistentWithTheGroundTruthPose) {
  for (const std::string& name : SyntheticPairPresetNames()) {
    const SyntheticPairOptions o = Preset(name);
    double max_clean_error = 0.0, max_noise_ratio = 0.0, max_lift_ratio = 0.0, max_sampson_ratio = 0.0;
    int outliers = 0, outliers_far = 0, inliers = 0;
    for (int seed = 0; seed < 20; ++seed) {
      const SyntheticPair s = GenerateTwoViewPair(o, seed);
      const Eigen::Matrix4d& T = *s.pair.T_0to1;
      const Eigen::Matrix3d R = T.block<3, 3>(0, 0);
      const Eigen::Vector3d t = T.block<3, 1>(0, 3);
      const Eigen::Matrix3d F = Fundamental(s);
      const double sigma = s.pixel_noise;
      const double noise_bound = 3.0 * std::sqrt(2.0) * sigma;  // per image: |noise| <= 3 sigma per coordinate
      for (size_t i = 0; i < s.pair.p0.size(); ++i) {
        const Eigen::Vector2d &p0 = s.pair.p0[i], &p1 = s.pair.p1[i];
        if (!s.is_inlier[i]) {
          ++outliers;
          if (Sampson(F, p0, p1) > 5.0) ++outliers_far;
          continue;
        }
        ++inliers;
        const Eigen::Vector3d& X0 = s.points0[i];
        const Eigen::Vector3d X1 = R * X0 + t;
        ASSERT_NEAR(X0.z(), s.true_depth0[i], 1e-9 * X0.z());
        ASSERT_NEAR(X1.z(), s.true_depth1[i], 1e-9 * X0.z());
        max_clean_error = std::max({max_clean_error, (Project(s.pair.K0, X0) - s.p0_clean[i]).norm(),
                                    (Project(s.pair.K1, X1) - s.p1_clean[i]).norm()});
        max_noise_ratio = std::max({max_noise_ratio, (p0 - s.p0_clean[i]).norm() / noise_bound,
                                    (p1 - s.p1_clean[i]).norm() / noise_bound});
        // Reprojection of the noisy p0 through the true depth: the noise of p0 moves the lifted point sideways by
        // about |noise| z0 / f0, which view 1 sees magnified by f1 / z1 (x2 for off-axis projection).
        const Eigen::Vector3d lifted = s.true_depth0[i] * (s.pair.K0.inverse() * p0.homogeneous());
        const double lift_error = (Project(s.pair.K1, R * lifted + t) - p1).norm();
        const double lift_bound =
            noise_bound * (1.0 + 2.0 * s.focal1 * s.true_depth0[i] / (s.focal0 * s.true_depth1[i]));
        max_lift_ratio = std::max(max_lift_ratio, lift_error / lift_bound);
        // The noise is a feasible perturbation of (p0, p1) of norm <= 6 sigma onto the epipolar variety.
        max_sampson_ratio = std::max(max_sampson_ratio, Sampson(F, p0, p1) / (6.0 * sigma));
      }
    }
    const double far_rate = static_cast<double>(outliers_far) / outliers;
    std::printf("[%s] %d inliers: max clean reprojection %.2e px, max noise / bound %.3f, max lifted reprojection "
                "/ bound %.3f, max Sampson / (6 sigma) %.3f; %d outliers: Sampson > 5 px for %.1f%%\n",
                name.c_str(), inliers, max_clean_error, max_noise_ratio, max_lift_ratio, max_sampson_ratio, outliers,
                100.0 * far_rate);
    EXPECT_LT(max_clean_error, 1e-6) << name;
    EXPECT_LE(max_noise_ratio, 1.0 + 1e-9) << name;
    EXPECT_LE(max_lift_ratio, 1.0) << name;
    EXPECT_LE(max_sampson_ratio, 1.05) << name;  // first-order distance vs an exact feasible perturbation
    EXPECT_GE(far_rate, 0.9) << name;
  }
}

TEST(TwoViewScene, InliersAreVisibleInBothViews) {
  // Each inlier's true depth in view 1 matches the rendered depth map of view 1 at its projection (a point hidden
  // behind a nearer surface would show a smaller rendered depth).
  for (const char* name : {"indoor_calibrated", "outdoor_calibrated"}) {
    const SyntheticPairOptions o = Preset(name);
    int total = 0, agree = 0, occluded = 0;
    for (int seed = 0; seed < 20; ++seed) {
      const SyntheticPair s = GenerateTwoViewPair(o, seed);
      for (size_t i = 0; i < s.pair.p0.size(); ++i) {
        if (!s.is_inlier[i]) continue;
        ++total;
        const double rendered = SampleMap(s.true_depth_map1, s.p1_clean[i], s.pair.width1, s.pair.height1);
        const double z1 = s.true_depth1[i];
        if (std::abs(rendered - z1) < 0.01 * z1) ++agree;
        // Bilinear samples straddling an edge mix depths: count only a clear, whole-pixel occlusion.
        const DepthMap& m = s.true_depth_map1;
        const double mu = (s.p1_clean[i].x() + 0.5) * m.width / s.pair.width1 - 0.5;
        const double mv = (s.p1_clean[i].y() + 0.5) * m.height / s.pair.height1 - 0.5;
        const int u = std::clamp(static_cast<int>(std::lround(mu)), 0, m.width - 1);
        const int v = std::clamp(static_cast<int>(std::lround(mv)), 0, m.height - 1);
        bool all_nearer = true;
        for (int dv = -1; dv <= 1; ++dv) {
          for (int du = -1; du <= 1; ++du) {
            const int uu = std::clamp(u + du, 0, m.width - 1), vv = std::clamp(v + dv, 0, m.height - 1);
            const double d = m.At(uu, vv);
            if (!(d > 0.0 && d < 0.8 * z1)) all_nearer = false;
          }
        }
        if (all_nearer) ++occluded;
      }
    }
    std::printf("[%s] %d inliers: view-1 rendered depth within 1%% for %.2f%%, clearly occluded %d\n", name,
                total, 100.0 * agree / total, occluded);
    EXPECT_GE(static_cast<double>(agree) / total, 0.95) << name;
    EXPECT_EQ(occluded, 0) << name;
  }
}

TEST(TwoViewScene, OutlierRatioIsMet) {
  SyntheticPairOptions o = Preset("indoor_calibrated");
  for (int n : {100, 500}) {
    for (double ratio : {0.0, 0.1, 0.35, 0.6}) {
      o.num_matches = n;
      o.min_outlier_ratio = o.max_outlier_ratio = ratio;
      for (int seed = 0; seed < 5; ++seed) {
        const SyntheticPair s = GenerateTwoViewPair(o, seed);
        ASSERT_EQ(static_cast<int>(s.pair.p0.size()), n);
        ASSERT_EQ(s.pair.p1.size(), s.pair.p0.size());
        int outliers = 0;
        for (uint8_t inlier : s.is_inlier) outliers += inlier ? 0 : 1;
        EXPECT_EQ(outliers, n - s.num_inliers);
        EXPECT_NEAR(static_cast<double>(outliers) / n, ratio, 0.5 / n + 1e-12);
        EXPECT_DOUBLE_EQ(s.outlier_ratio, static_cast<double>(outliers) / n);
      }
    }
  }
  // Default range 0.1-0.6 per pair.
  o = Preset("outdoor_calibrated");
  double sum = 0.0, lo = 1.0, hi = 0.0;
  const int count = 100;
  for (const SyntheticPair& s : GenerateTwoViewSet(o, count, 5)) {
    sum += s.outlier_ratio;
    lo = std::min(lo, s.outlier_ratio);
    hi = std::max(hi, s.outlier_ratio);
  }
  std::printf("default outlier ratio over %d pairs: mean %.3f, min %.3f, max %.3f\n", count, sum / count, lo, hi);
  EXPECT_GE(lo, 0.1 - 1.0 / o.num_matches);
  EXPECT_LE(hi, 0.6 + 1.0 / o.num_matches);
  EXPECT_NEAR(sum / count, 0.35, 0.05);
}

TEST(TwoViewScene, DepthMapsHaveTheRequestedResolutionAndArePositive) {
  struct Case {
    SyntheticSceneType scene;
    int width, height;
    double scale;
    int expected_w, expected_h;
  };
  const Case cases[] = {{SyntheticSceneType::kIndoor, 0, 0, 0.0, 320, 240},
                        {SyntheticSceneType::kOutdoor, 0, 0, 0.0, 256, 192},
                        {SyntheticSceneType::kIndoor, 640, 480, 0.25, 160, 120},
                        {SyntheticSceneType::kIndoor, 640, 480, 1.0 / 3.0, 213, 160},
                        {SyntheticSceneType::kOutdoor, 800, 600, 0.5, 400, 300}};
  for (const Case& c : cases) {
    SyntheticPairOptions o;
    o.scene = c.scene;
    o.image_width = c.width;
    o.image_height = c.height;
    o.depth_map_scale = c.scale;
    for (int seed = 0; seed < 5; ++seed) {
      const SyntheticPair s = GenerateTwoViewPair(o, seed);
      const int w = c.width ? c.width : (c.scene == SyntheticSceneType::kIndoor ? 640 : 1024);
      const int h = c.height ? c.height : (c.scene == SyntheticSceneType::kIndoor ? 480 : 768);
      EXPECT_EQ(s.pair.width0, w);
      EXPECT_EQ(s.pair.height0, h);
      EXPECT_EQ(s.pair.width1, w);
      EXPECT_EQ(s.pair.height1, h);
      for (const DepthMap* m : {&*s.pair.depth0, &*s.pair.depth1, &s.true_depth_map0, &s.true_depth_map1}) {
        ASSERT_EQ(m->width, c.expected_w);
        ASSERT_EQ(m->height, c.expected_h);
        ASSERT_EQ(m->data.size(), static_cast<size_t>(c.expected_w) * c.expected_h);
      }
      ASSERT_EQ(s.wild_mask0.size(), s.pair.depth0->data.size());
      for (const DepthMap* m : {&*s.pair.depth0, &*s.pair.depth1}) {
        for (float v : m->data) ASSERT_TRUE(std::isfinite(v) && v > 0.0f);
      }
      for (const DepthMap* m : {&s.true_depth_map0, &s.true_depth_map1}) {
        int valid = 0;
        for (float v : m->data) {
          ASSERT_TRUE(std::isfinite(v) && v >= 0.0f);
          if (v > 0.0f) {
            ++valid;
            if (c.scene == SyntheticSceneType::kIndoor) {
              ASSERT_GT(v, 0.05f);
              ASSERT_LT(v, 12.0f);
            } else {
              ASSERT_GT(v, 0.5f);
              ASSERT_LT(v, 205.0f);
            }
          }
        }
        if (c.scene == SyntheticSceneType::kIndoor) {
          EXPECT_EQ(valid, m->width * m->height);  // a closed room: no sky
        } else {
          EXPECT_GT(valid, 0.4 * m->width * m->height);  // sky in at most half of a coarse grid per view
        }
      }
    }
  }
}

TEST(TwoViewScene, TrueAffineTransformReproducesTrueDepth) {
  for (SyntheticSceneType scene : {SyntheticSceneType::kIndoor, SyntheticSceneType::kOutdoor}) {
    for (SyntheticPriorType type : {SyntheticPriorType::kDepth, SyntheticPriorType::kDisparity}) {
      SyntheticPairOptions o;
      o.scene = scene;
      o.prior = DepthPriorCorruption::AffineOnly();
      o.prior.type = type;
      double max_rel = 0.0;
      std::vector<double> sample_errors;
      for (int seed = 0; seed < 10; ++seed) {
        const SyntheticPair s = GenerateTwoViewPair(o, seed);
        EXPECT_EQ(s.prior_type, type);
        for (int view = 0; view < 2; ++view) {
          const DepthMap& prior = view == 0 ? *s.pair.depth0 : *s.pair.depth1;
          const DepthMap& truth = view == 0 ? s.true_depth_map0 : s.true_depth_map1;
          const double a = view == 0 ? s.prior_scale0 : s.prior_scale1;
          const double b = view == 0 ? s.prior_shift0 : s.prior_shift1;
          EXPECT_GE(a, o.prior.min_scale);
          EXPECT_LE(a, o.prior.max_scale);
          for (size_t i = 0; i < prior.data.size(); ++i) {
            if (truth.data[i] <= 0.0f) continue;
            const double v = a * prior.data[i] + b;
            const double z = type == SyntheticPriorType::kDepth ? v : 1.0 / v;
            max_rel = std::max(max_rel, std::abs(z - truth.data[i]) / truth.data[i]);
          }
        }
        // The map-to-image sampling rule: the rendered true depth sampled at an inlier's exact pixel gives its depth.
        for (size_t i = 0; i < s.pair.p0.size(); ++i) {
          if (!s.is_inlier[i]) continue;
          const double z = SampleMap(s.true_depth_map0, s.p0_clean[i], s.pair.width0, s.pair.height0);
          sample_errors.push_back(std::abs(z - s.true_depth0[i]) / s.true_depth0[i]);
        }
      }
      std::sort(sample_errors.begin(), sample_errors.end());
      const double median = sample_errors[sample_errors.size() / 2];
      const double within = static_cast<double>(std::lower_bound(sample_errors.begin(), sample_errors.end(), 1e-3) -
                                                sample_errors.begin()) / sample_errors.size();
      std::printf("[%s, %s] affine-only priors: max relative error of the true transform %.2e; true depth map "
                  "sampled at inliers: median relative error %.2e, within 0.1%% for %.1f%%\n",
                  scene == SyntheticSceneType::kIndoor ? "indoor" : "outdoor",
                  type == SyntheticPriorType::kDepth ? "depth" : "disparity", max_rel, median, 100.0 * within);
      EXPECT_LT(max_rel, 1e-5);  // float storage
      EXPECT_LT(median, 1e-4);
      EXPECT_GE(within, 0.9);
    }
  }
}

TEST(TwoViewScene, TrueModelMatchesTheAffineDepthPoseConvention) {
  // Lifting the exact priors of an inlier with the corrected depths of TrueModel() must give points related by
  // X1 = R X0 + t_model.
  for (const char* name : {"indoor_two_focal", "outdoor_calibrated"}) {
    const SyntheticPairOptions o = Preset(name);
    double max_error = 0.0;
    for (int seed = 0; seed < 10; ++seed) {
      const SyntheticPair s = GenerateTwoViewPair(o, seed);
      const AffineDepthPose m = s.TrueModel();
      EXPECT_DOUBLE_EQ(m.f0, s.pair.K0(0, 0));
      EXPECT_DOUBLE_EQ(m.f1, s.pair.K1(0, 0));
      for (size_t i = 0; i < s.pair.p0.size(); ++i) {
        if (!s.is_inlier[i]) continue;
        const double d0 = (s.true_depth0[i] - s.prior_shift0) / s.prior_scale0;
        const double d1 = (s.true_depth1[i] - s.prior_shift1) / s.prior_scale1;
        const Eigen::Vector3d X0 = m.Depth0(d0) * (s.pair.K0.inverse() * s.p0_clean[i].homogeneous());
        const Eigen::Vector3d X1 = m.Depth1(d1) * (s.pair.K1.inverse() * s.p1_clean[i].homogeneous());
        max_error = std::max(max_error, (m.R * X0 + m.t - X1).norm() / X1.norm());
      }
    }
    std::printf("[%s] TrueModel: max relative 3-D error %.2e\n", name, max_error);
    EXPECT_LT(max_error, 1e-9);
  }
  // Disparity priors without shift, inverted (D = 1 / s): a scale-only model.
  SyntheticPairOptions o = Preset("indoor_calibrated");
  o.prior = DepthPriorCorruption::AffineOnly();
  o.prior.type = SyntheticPriorType::kDisparity;
  o.prior.max_shift_fraction = 0.0;
  double max_error = 0.0;
  for (int seed = 0; seed < 10; ++seed) {
    const SyntheticPair s = GenerateTwoViewPair(o, seed);
    EXPECT_EQ(s.prior_shift0, 0.0);
    const AffineDepthPose m = s.TrueModel();
    EXPECT_EQ(m.shift0, 0.0);
    EXPECT_EQ(m.shift1, 0.0);
    for (size_t i = 0; i < s.pair.p0.size(); ++i) {
      if (!s.is_inlier[i]) continue;
      const double D0 = s.prior_scale0 * s.true_depth0[i], D1 = s.prior_scale1 * s.true_depth1[i];  // 1 / s
      const Eigen::Vector3d X0 = m.Depth0(D0) * (s.pair.K0.inverse() * s.p0_clean[i].homogeneous());
      const Eigen::Vector3d X1 = m.Depth1(D1) * (s.pair.K1.inverse() * s.p1_clean[i].homogeneous());
      max_error = std::max(max_error, (m.R * X0 + m.t - X1).norm() / X1.norm());
    }
  }
  std::printf("[inverted disparity, no shift] TrueModel: max relative 3-D error %.2e\n", max_error);
  EXPECT_LT(max_error, 1e-9);
}

// Median over valid pixels of |a prior + b - z| / z for both views of count pairs; also the wild-region share.
void PriorQuality(const SyntheticPairOptions& o, int count, double* median_error, double* mean_error,
                  double* wild_share) {
  std::vector<double> errors;
  *mean_error = 0.0;
  long wild = 0, total = 0;
  for (int seed = 0; seed < count; ++seed) {
    const SyntheticPair s = GenerateTwoViewPair(o, seed);
    for (int view = 0; view < 2; ++view) {
      const DepthMap& prior = view == 0 ? *s.pair.depth0 : *s.pair.depth1;
      const DepthMap& truth = view == 0 ? s.true_depth_map0 : s.true_depth_map1;
      const std::vector<uint8_t>& mask = view == 0 ? s.wild_mask0 : s.wild_mask1;
      const double a = view == 0 ? s.prior_scale0 : s.prior_scale1;
      const double b = view == 0 ? s.prior_shift0 : s.prior_shift1;
      for (size_t i = 0; i < prior.data.size(); i += 7) {
        if (truth.data[i] <= 0.0f) continue;
        errors.push_back(std::abs(a * prior.data[i] + b - truth.data[i]) / truth.data[i]);
        *mean_error += errors.back();
      }
      for (uint8_t w : mask) wild += w;
      total += static_cast<long>(mask.size());
    }
  }
  std::sort(errors.begin(), errors.end());
  *median_error = errors[errors.size() / 2];
  *mean_error /= errors.size();
  *wild_share = static_cast<double>(wild) / total;
}

TEST(TwoViewScene, TypicalPriorsAreCloseAndBadPriorsAreFar) {
  double typical_error, typical_mean, typical_wild, bad_error, bad_mean, bad_wild, outdoor_error, outdoor_mean,
      outdoor_wild;
  const SyntheticPairOptions typical = Preset("indoor_calibrated");
  const SyntheticPairOptions bad = Preset("indoor_bad_prior");
  const SyntheticPairOptions outdoor = Preset("outdoor_calibrated");
  PriorQuality(typical, 20, &typical_error, &typical_mean, &typical_wild);
  PriorQuality(bad, 20, &bad_error, &bad_mean, &bad_wild);
  PriorQuality(outdoor, 20, &outdoor_error, &outdoor_mean, &outdoor_wild);
  std::printf("relative error of the prior under the true affine transform (median / mean): typical indoor "
              "%.3f / %.3f (wild share %.3f), outdoor %.3f / %.3f (wild %.3f), bad prior %.3f / %.3f (wild %.3f)\n",
              typical_error, typical_mean, typical_wild, outdoor_error, outdoor_mean, outdoor_wild, bad_error,
              bad_mean, bad_wild);
  EXPECT_GT(typical_error, 0.005);  // the priors are corrupted, not exact
  EXPECT_LT(typical_error, 0.08);
  EXPECT_LT(outdoor_error, 0.08);
  EXPECT_GT(bad_error, 0.2);
  // Blobs are clipped by the map border and may overlap: at most the requested share, at least a fair part of it.
  EXPECT_LE(typical_wild, typical.prior.wild_region_fraction * 1.05);
  EXPECT_GE(typical_wild, typical.prior.wild_region_fraction * 0.4);
  EXPECT_LE(bad_wild, bad.prior.wild_region_fraction * 1.05);
  EXPECT_GE(bad_wild, bad.prior.wild_region_fraction * 0.4);
}

TEST(TwoViewScene, EachPresetProducesValidPairs) {
  for (const std::string& name : SyntheticPairPresetNames()) {
    if (name.rfind("hard_", 0) == 0) continue;  // per-pair ranges: HardPresetsDrawTheirRanges
    const SyntheticPairOptions o = Preset(name);
    const bool indoor = o.scene == SyntheticSceneType::kIndoor;
    double max_rotation = 0.0, min_baseline = 1e9, max_baseline = 0.0, min_median = 1e9, max_median = 0.0;
    double min_fov = 1e9, max_fov = 0.0;
    for (int seed = 0; seed < 50; ++seed) {
      const SyntheticPair s = GenerateTwoViewPair(o, 1000 + seed);
      const PairData& p = s.pair;
      ASSERT_EQ(static_cast<int>(p.p0.size()), o.num_matches) << name << " seed " << seed;
      ASSERT_EQ(s.is_inlier.size(), p.p0.size());
      ASSERT_TRUE(p.T_0to1.has_value());
      ASSERT_TRUE(p.depth0.has_value() && p.depth1.has_value());
      EXPECT_EQ(s.scene, o.scene);
      EXPECT_EQ(s.camera_setup, o.camera_setup);
      EXPECT_EQ(p.width0, indoor ? 640 : 1024);
      EXPECT_EQ(p.height0, indoor ? 480 : 768);
      EXPECT_EQ(p.depth0->width, indoor ? 320 : 256);
      // Pose.
      const Eigen::Matrix3d R = p.T_0to1->block<3, 3>(0, 0);
      EXPECT_LT((R * R.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
      EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
      const double angle = Eigen::AngleAxisd(R).angle() * 180.0 / kPi;
      EXPECT_NEAR(angle, s.rotation_deg, 1e-6);
      EXPECT_LE(s.rotation_deg, o.max_rotation_deg + 1e-9);
      max_rotation = std::max(max_rotation, s.rotation_deg);
      const double t_norm = p.T_0to1->block<3, 1>(0, 3).norm();
      EXPECT_NEAR(t_norm, s.baseline, 1e-9 * s.baseline);
      const double rel_baseline = s.baseline / s.median_depth0;
      min_baseline = std::min(min_baseline, rel_baseline);
      max_baseline = std::max(max_baseline, rel_baseline);
      min_median = std::min(min_median, s.median_depth0);
      max_median = std::max(max_median, s.median_depth0);
      // Intrinsics.
      for (const Eigen::Matrix3d* K : {&p.K0, &p.K1}) {
        EXPECT_EQ((*K)(0, 0), (*K)(1, 1));
        EXPECT_EQ((*K)(0, 1), 0.0);
        const double fov = 2.0 * std::atan(0.5 * p.width0 / (*K)(0, 0)) * 180.0 / kPi;
        min_fov = std::min(min_fov, fov);
        max_fov = std::max(max_fov, fov);
        EXPECT_GE(fov, o.min_fov_deg - 1e-9);
        EXPECT_LE(fov, o.max_fov_deg + 1e-9);
        EXPECT_LE(std::abs((*K)(0, 2) - 0.5 * (p.width0 - 1)), o.principal_point_jitter * p.width0 + 1e-9);
        EXPECT_LE(std::abs((*K)(1, 2) - 0.5 * (p.height0 - 1)), o.principal_point_jitter * p.height0 + 1e-9);
      }
      EXPECT_EQ(s.focal0, p.K0(0, 0));
      EXPECT_EQ(s.focal1, p.K1(0, 0));
      if (o.camera_setup == SyntheticCameraSetup::kTwoFocal) {
        EXPECT_NE(p.K0(0, 0), p.K1(0, 0));
      } else {
        EXPECT_EQ(p.K0, p.K1);
      }
      // Matches and ground truth.
      EXPECT_GE(s.outlier_ratio, o.min_outlier_ratio - 1.0 / o.num_matches);
      EXPECT_LE(s.outlier_ratio, o.max_outlier_ratio + 1.0 / o.num_matches);
      EXPECT_GE(s.pixel_noise, o.min_pixel_noise);
      EXPECT_LE(s.pixel_noise, o.max_pixel_noise);
      for (size_t i = 0; i < p.p0.size(); ++i) {
        for (const Eigen::Vector2d* q : {&p.p0[i], &p.p1[i]}) {
          ASSERT_TRUE(q->allFinite());
          ASSERT_GE(q->x(), -0.5);
          ASSERT_LE(q->x(), p.width0 - 0.5);
          ASSERT_GE(q->y(), -0.5);
          ASSERT_LE(q->y(), p.height0 - 0.5);
        }
        if (s.is_inlier[i]) {
          ASSERT_GT(s.true_depth0[i], 0.0);
          ASSERT_GT(s.true_depth1[i], 0.0);
        }
      }
      for (const DepthMap* m : {&*p.depth0, &*p.depth1}) {
        for (float v : m->data) ASSERT_TRUE(std::isfinite(v) && v > 0.0f);
      }
      const AffineDepthPose model = s.TrueModel();
      EXPECT_TRUE(model.R.allFinite() && model.t.allFinite() && std::isfinite(model.scale) && model.scale > 0.0);
      EXPECT_TRUE(std::isfinite(model.shift0) && std::isfinite(model.shift1));
    }
    std::printf("[%s] 50 pairs: max rotation %.1f deg, baseline / median depth %.3f-%.3f, median depth %.2f-%.2f m, "
                "FOV %.1f-%.1f deg\n",
                name.c_str(), max_rotation, min_baseline, max_baseline, min_median, max_median, min_fov, max_fov);
    // The baseline is drawn relative to the median of a coarse grid of view 0; the map median differs a little.
    EXPECT_GE(min_baseline, 0.5 * o.baseline_min) << name;
    EXPECT_LE(max_baseline, 2.0 * o.baseline_max) << name;
    EXPECT_GE(min_median, indoor ? 0.5 : 2.0) << name;
    EXPECT_LE(max_median, indoor ? 8.0 : 200.0) << name;
  }
}

// The hard presets (issue 12) draw match count, noise, cameras, depth scales, metric or affine priors and edge
// keypoints per pair: check the ranges are honoured and actually used, and that the ground truth still holds.
TEST(TwoViewScene, HardPresetsDrawTheirRanges) {
  for (const std::string& name : SyntheticPairPresetNames()) {
    if (name.rfind("hard_", 0) != 0) continue;
    const SyntheticPairOptions o = Preset(name);
    const bool outdoor = o.scene == SyntheticSceneType::kOutdoor;
    int min_matches = 1 << 30, max_matches = 0, metric = 0, two_cameras = 0, near_edges = 0, inliers = 0;
    const int n = 16;
    for (int seed = 0; seed < n; ++seed) {
      const SyntheticPair s = GenerateTwoViewPair(o, 500 + seed);
      const PairData& p = s.pair;
      const int m = static_cast<int>(p.p0.size());
      min_matches = std::min(min_matches, m);
      max_matches = std::max(max_matches, m);
      EXPECT_LE(m, o.max_num_matches) << name;
      EXPECT_GE(s.pixel_noise, 0.5);
      EXPECT_LE(s.pixel_noise, 1.5);
      EXPECT_EQ(p.width0, outdoor ? 1024 : 640);
      EXPECT_EQ(p.depth0->width, p.width0 / 2);  // half resolution
      two_cameras += p.K0 != p.K1;
      // Depth scales within 2x of each other; nearly metric pairs have both in [0.8, 1.25].
      const double ratio = s.prior_scale1 / s.prior_scale0;
      EXPECT_GE(ratio, 0.5 - 1e-12) << name;
      EXPECT_LE(ratio, 2.0 + 1e-12) << name;
      metric += s.prior_scale0 >= 0.8 && s.prior_scale0 <= 1.25 && s.prior_scale1 >= 0.8 && s.prior_scale1 <= 1.25;
      // Inliers: the true depth lifted with the true pose lands on p1 (within the noise), and some keypoints lie
      // next to a depth jump of the true depth map.
      const Eigen::Matrix3d R = p.T_0to1->block<3, 3>(0, 0);
      const Eigen::Vector3d t = p.T_0to1->block<3, 1>(0, 3);
      const DepthMap& z = s.true_depth_map0;
      for (int i = 0; i < m; ++i) {
        if (!s.is_inlier[i]) continue;
        ++inliers;
        const Eigen::Vector3d X1 = R * s.points0[i] + t;
        const Eigen::Vector3d h = p.K1 * X1;
        ASSERT_LT((h.head<2>() / h.z() - s.p1_clean[i]).norm(), 1e-6) << name;
        const int u = std::clamp(static_cast<int>((p.p0[i].x() + 0.5) * z.width / p.width0), 1, z.width - 2);
        const int v = std::clamp(static_cast<int>((p.p0[i].y() + 0.5) * z.height / p.height0), 1, z.height - 2);
        double lo = 1e30, hi = 0.0;
        for (int dv = -1; dv <= 1; ++dv) {
          for (int du = -1; du <= 1; ++du) {
            const double d = z.data[static_cast<size_t>(v + dv) * z.width + u + du];
            if (d > 0.0) lo = std::min(lo, d), hi = std::max(hi, d);
          }
        }
        near_edges += hi > 1.05 * lo;
      }
    }
    std::printf("[%s] %d pairs: %d-%d matches, %d nearly metric, %d with two cameras, %.1f%% inliers near edges\n",
                name.c_str(), n, min_matches, max_matches, metric, two_cameras, 100.0 * near_edges / inliers);
    EXPECT_GE(min_matches, 100) << name;  // 150 requested; a pair with little overlap may get fewer
    EXPECT_GT(max_matches - min_matches, 500) << name;
    EXPECT_GE(metric, 3) << name;  // half of the pairs, drawn
    EXPECT_LE(metric, n - 3) << name;
    if (o.camera_setup != SyntheticCameraSetup::kSharedFocal) {
      EXPECT_EQ(two_cameras, n) << name;
    }
    if (o.scene != SyntheticSceneType::kPlanar) {
      EXPECT_GE(near_edges, 0.03 * inliers) << name;
    }
  }
}

TEST(TwoViewScene, PresetsAndOptionChecks) {
  for (const std::string& name : SyntheticPairPresetNames()) {
    const std::optional<SyntheticPairOptions> o = SyntheticPairPreset(name);
    ASSERT_TRUE(o.has_value()) << name;
    EXPECT_NO_THROW(o->Check());
  }
  EXPECT_FALSE(SyntheticPairPreset("no_such_preset").has_value());
  EXPECT_EQ(Preset("indoor_bad_prior").prior.distortion, DepthPriorCorruption::Bad().distortion);
  EXPECT_EQ(Preset("outdoor_two_focal").scene, SyntheticSceneType::kOutdoor);

  auto expect_invalid = [](auto mutate) {
    SyntheticPairOptions o;
    mutate(o);
    EXPECT_THROW(o.Check(), std::invalid_argument);
    EXPECT_THROW(GenerateTwoViewPair(o, 1), std::invalid_argument);
  };
  expect_invalid([](SyntheticPairOptions& o) { o.depth_map_scale = 1.5; });
  expect_invalid([](SyntheticPairOptions& o) { o.image_width = 640; });
  expect_invalid([](SyntheticPairOptions& o) { o.min_fov_deg = 120; });
  expect_invalid([](SyntheticPairOptions& o) { o.max_outlier_ratio = 1.0; });
  expect_invalid([](SyntheticPairOptions& o) { o.num_matches = -1; });
  expect_invalid([](SyntheticPairOptions& o) { o.baseline_min = 0.0; });
  expect_invalid([](SyntheticPairOptions& o) { o.prior.min_scale = 0.0; });
  expect_invalid([](SyntheticPairOptions& o) { o.prior.blur_sigma_px = -1.0; });
  expect_invalid([](SyntheticPairOptions& o) { o.max_num_matches = -1; });
  expect_invalid([](SyntheticPairOptions& o) { o.max_edge_fraction = 1.5; });
  expect_invalid([](SyntheticPairOptions& o) { o.prior.max_scale_ratio = 0.5; });
  expect_invalid([](SyntheticPairOptions& o) { o.prior.metric_fraction = 2.0; });
}

}  // namespace
}  // namespace madsfm
