#include "madsfm/solvers/hessenberg_eigenvalues.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <complex>
#include <random>
#include <vector>

namespace madsfm {
namespace {

using Complex = std::complex<double>;

// Largest distance from an eigenvalue of `reference` to the nearest unused one of (real, imag), after
// matching them greedily (each used once).
double MatchDistance(const std::vector<Complex>& reference, const double* real, const double* imag) {
  const int n = static_cast<int>(reference.size());
  std::vector<bool> used(n, false);
  double worst = 0.0;
  for (const Complex& r : reference) {
    int best = -1;
    double best_d = 0.0;
    for (int k = 0; k < n; ++k) {
      if (used[k]) continue;
      const double d = std::abs(r - Complex(real[k], imag[k]));
      if (best < 0 || d < best_d) best = k, best_d = d;
    }
    used[best] = true;
    worst = std::max(worst, best_d);
  }
  return worst;
}

double RelativeDistance(const std::vector<Complex>& expected, const std::vector<Complex>& found) {
  std::vector<double> real, imag;
  for (const Complex& c : found) real.push_back(c.real()), imag.push_back(c.imag());
  double size = 0.0;
  for (const Complex& e : expected) size = std::max(size, std::abs(e));
  return MatchDistance(expected, real.data(), imag.data()) / std::max(size, 1e-300);
}

std::vector<Complex> EigenEigenvalues(const Eigen::MatrixXd& A) {
  const Eigen::EigenSolver<Eigen::MatrixXd> solver(A, /*computeEigenvectors=*/false);
  EXPECT_EQ(solver.info(), Eigen::Success);
  return {solver.eigenvalues().data(), solver.eigenvalues().data() + A.rows()};
}

// Eigenvalues of A (through its Hessenberg form) against `expected`, as a distance relative to the
// size of the eigenvalues; also checks the layout of complex pairs.
double CheckEigenvalues(const Eigen::MatrixXd& A, const std::vector<Complex>& expected) {
  const int n = static_cast<int>(A.rows());
  Eigen::MatrixXd H = Eigen::HessenbergDecomposition<Eigen::MatrixXd>(A).matrixH();
  std::vector<double> real(n), imag(n);
  EXPECT_TRUE(HessenbergEigenvalues(H, real.data(), imag.data()));
  // Complex pairs come as conjugates, the positive imaginary part first.
  for (int k = 0; k < n; ++k) {
    if (imag[k] > 0.0) {
      EXPECT_LT(k + 1, n);
      if (k + 1 < n) {
        EXPECT_EQ(real[k + 1], real[k]);
        EXPECT_EQ(imag[k + 1], -imag[k]);
      }
      ++k;
    } else {
      EXPECT_EQ(imag[k], 0.0) << "eigenvalue " << k;
    }
  }
  std::vector<Complex> found;
  for (int k = 0; k < n; ++k) found.emplace_back(real[k], imag[k]);
  return RelativeDistance(expected, found);
}

// Random matrices, against Eigen's real Schur decomposition. The same matrices with rows and columns
// on scales up to 1e+-6 apart (as in the solvers' matrices) are a similarity, so their eigenvalues are
// those of the unscaled matrix; without balancing neither method reaches them to full precision, and
// HessenbergEigenvalues must be about as close as Eigen is on the same scaled matrix.
TEST(HessenbergEigenvalues, AgreesWithEigenOnRandomMatrices) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0.0, 1.0);
  double worst = 0.0, worst_scaled = 0.0, worst_scaled_eigen = 0.0;
  int less_accurate = 0;
  for (int n : {1, 2, 3, 4, 5, 8, 15, 16, 20, 32}) {
    for (int trial = 0; trial < 25; ++trial) {
      Eigen::MatrixXd A(n, n);
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) A(i, j) = g(rng);
      const std::vector<Complex> expected = EigenEigenvalues(A);
      worst = std::max(worst, CheckEigenvalues(A, expected));
      for (int i = 0; i < n; ++i) {
        const double s = std::pow(10.0, std::uniform_real_distribution<double>(-3.0, 3.0)(rng));
        A.row(i) *= s;
        A.col(i) /= s;
      }
      const double ours = CheckEigenvalues(A, expected);
      const double eigen = RelativeDistance(expected, EigenEigenvalues(A));
      worst_scaled = std::max(worst_scaled, ours);
      worst_scaled_eigen = std::max(worst_scaled_eigen, eigen);
      less_accurate += ours > 10.0 * eigen + 1e-13;
    }
  }
  std::printf("hessenberg_eigenvalues: worst distance to Eigen's eigenvalues %.2e; with scaled rows %.2e "
              "(Eigen itself: %.2e); relative to the largest eigenvalue\n", worst, worst_scaled, worst_scaled_eigen);
  EXPECT_LT(worst, 1e-12);
  // Rounding decides these errors: a few matrices may come out worse, the worst case no more than Eigen's.
  EXPECT_LE(less_accurate, 5) << "of 250 scaled matrices more than 10x less accurate than Eigen";
  EXPECT_LE(worst_scaled, 3.0 * worst_scaled_eigen);
}

TEST(HessenbergEigenvalues, FindsKnownEigenvaluesIncludingClustersAndRepeats) {
  std::mt19937 rng(11);
  std::normal_distribution<double> g(0.0, 1.0);
  // A = V diag(lambda) V^-1 with known eigenvalues: a cluster, a repeated value, zero, and a complex pair
  // (as a 2 x 2 rotation-scaling block).
  const int n = 12;
  const double known[] = {3.0, 3.001, 3.002, 3.0005, -1.0, -1.0, 0.0, 10.0, 1e-3, 250.0};
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::MatrixXd D = Eigen::MatrixXd::Zero(n, n);
    for (int k = 0; k < 10; ++k) D(k, k) = known[k];
    D(10, 10) = D(11, 11) = 2.0;
    D(10, 11) = 0.5;
    D(11, 10) = -0.5;
    Eigen::MatrixXd V(n, n);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) V(i, j) = g(rng);
    const Eigen::MatrixXd A = V * D * V.inverse();
    Eigen::MatrixXd H = Eigen::HessenbergDecomposition<Eigen::MatrixXd>(A).matrixH();
    double real[n], imag[n];
    ASSERT_TRUE(HessenbergEigenvalues(H, real, imag));
    std::vector<Complex> expected(known, known + 10);
    expected.emplace_back(2.0, 0.5);
    expected.emplace_back(2.0, -0.5);
    // The repeated eigenvalue -1 (a double root) is only determined to about sqrt(eps) * ||A||.
    EXPECT_LT(MatchDistance(expected, real, imag), 1e-6 * A.norm()) << "trial " << trial;
  }
}

TEST(HessenbergEigenvalues, HandlesSplitMatricesAndBadInput) {
  // Already triangular (every subdiagonal zero), and a zero matrix.
  Eigen::MatrixXd T(4, 4);
  T << 1, 2, 3, 4, 0, 5, 6, 7, 0, 0, -8, 9, 0, 0, 0, 10;
  double real[4], imag[4];
  ASSERT_TRUE(HessenbergEigenvalues(T, real, imag));
  std::vector<double> sorted(real, real + 4);
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(sorted, (std::vector<double>{-8, 1, 5, 10}));
  for (double v : imag) EXPECT_EQ(v, 0.0);
  Eigen::MatrixXd Z = Eigen::MatrixXd::Zero(3, 3);
  ASSERT_TRUE(HessenbergEigenvalues(Z, real, imag));
  for (int k = 0; k < 3; ++k) EXPECT_EQ(std::abs(real[k]) + std::abs(imag[k]), 0.0);
  // A rotation by 90 degrees: +-i.
  Eigen::MatrixXd R(2, 2);
  R << 0, -1, 1, 0;
  ASSERT_TRUE(HessenbergEigenvalues(R, real, imag));
  EXPECT_DOUBLE_EQ(real[0], 0.0);
  EXPECT_DOUBLE_EQ(imag[0], 1.0);
  EXPECT_DOUBLE_EQ(imag[1], -1.0);
  // Non-finite entries and sizes out of range are refused.
  Eigen::MatrixXd bad = Eigen::MatrixXd::Identity(3, 3);
  bad(1, 0) = std::nan("");
  EXPECT_FALSE(HessenbergEigenvalues(bad, real, imag));
  Eigen::MatrixXd empty(0, 0);
  EXPECT_FALSE(HessenbergEigenvalues(empty, real, imag));
  std::vector<double> big(kMaxHessenbergOrder + 1);
  Eigen::MatrixXd too_big = Eigen::MatrixXd::Identity(kMaxHessenbergOrder + 1, kMaxHessenbergOrder + 1);
  EXPECT_FALSE(HessenbergEigenvalues(too_big, big.data(), big.data()));
}

}  // namespace
}  // namespace madsfm
