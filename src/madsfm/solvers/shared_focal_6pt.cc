#include "madsfm/solvers/shared_focal_6pt.h"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <limits>

#include "madsfm/solvers/hessenberg_eigenvalues.h"

// Method. The 6 epipolar constraints leave a 3-dimensional space F = x F1 + y F2 + F3. With
// K = diag(f, f, 1), E = K F K is essential iff det(F) = 0 and 2 F Q F^T Q F - tr(F Q F^T Q) F = 0
// with Q = diag(1, 1, w), w = 1 / f^2 (the trace constraint of E, divided by K on both sides and by
// f^4). In the monomials m = [x^3, x^2 y, x y^2, y^3, x^2, x y, y^2, x, y, 1] these 10 equations
// read (C0 + w C1 + w^2 C2) m = 0. Every w^2 term carries the factor F33 (entry (2, 2)), so
// C2 = G H with H (6x10) the coefficients of F33 * [x^2, x y, y^2, x, y, 1] and G (10x6): rank 6.
// With n = w H m and mu = 1 / w = f^2 the quadratic eigenvalue problem becomes the 16x16
// eigenproblem mu [m; n] = [-C0^-1 C1, -C0^-1 G; H, 0] [m; n] (one extra eigenvalue, mu = 0), solved
// for its eigenvalues only (Hessenberg form, then HessenbergEigenvalues).
// Real eigenvalues mu > 0 give candidates; x, y come from the null vector of C0 + w C1 + w^2 C2,
// (x, y, w) are polished by Gauss-Newton on the 10 equations and every candidate is verified
// (E = K F K essential to 1e-9) before it is returned. F is returned with unit Frobenius norm.

namespace madsfm {
namespace {

using Lin = Eigen::Vector3d;                 // coefficients of [x, y, 1]
using Quad = Eigen::Matrix<double, 6, 1>;    // coefficients of [x^2, x y, y^2, x, y, 1]
using Cubic = Eigen::Matrix<double, 10, 1>;  // [x^3, x^2 y, x y^2, y^3, x^2, x y, y^2, x, y, 1]
using Mat10 = Eigen::Matrix<double, 10, 10>;
using Mat16 = Eigen::Matrix<double, 16, 16>;

constexpr int kMaxSolutions = 15;

Quad Mul11(const Lin& a, const Lin& b) {
  Quad q;
  q << a[0] * b[0], a[0] * b[1] + a[1] * b[0], a[1] * b[1], a[0] * b[2] + a[2] * b[0], a[1] * b[2] + a[2] * b[1],
      a[2] * b[2];
  return q;
}

Cubic Mul12(const Lin& a, const Quad& q) {
  Cubic c;
  c << a[0] * q[0], a[0] * q[1] + a[1] * q[0], a[0] * q[2] + a[1] * q[1], a[1] * q[2], a[0] * q[3] + a[2] * q[0],
      a[0] * q[4] + a[1] * q[3] + a[2] * q[1], a[1] * q[4] + a[2] * q[2], a[0] * q[5] + a[2] * q[3],
      a[1] * q[5] + a[2] * q[4], a[2] * q[5];
  return c;
}

// Monomial vector m(x, y) and its partial derivatives.
void Monomials(double x, double y, Cubic* m, Cubic* dx, Cubic* dy) {
  *m << x * x * x, x * x * y, x * y * y, y * y * y, x * x, x * y, y * y, x, y, 1.0;
  *dx << 3 * x * x, 2 * x * y, y * y, 0.0, 2 * x, y, 0.0, 1.0, 0.0, 0.0;
  *dy << 0.0, x * x, 2 * x * y, 3 * y * y, 0.0, x, 2 * y, 0.0, 1.0, 0.0;
}

// Null vector z of a (numerically) rank-9 10x10 matrix by Gaussian elimination with complete pivoting;
// false if the matrix has rank < 9 or is not finite.
bool NullVector(const Mat10& matrix, Cubic* z) {
  double A[10][10];
  double a_max = 0.0;
  for (int r = 0; r < 10; ++r)
    for (int c = 0; c < 10; ++c) {
      A[r][c] = matrix(r, c);
      a_max = std::max(a_max, std::abs(A[r][c]));
    }
  if (!(a_max > 0.0) || !std::isfinite(a_max)) return false;
  int col_perm[10];
  for (int i = 0; i < 10; ++i) col_perm[i] = i;
  for (int k = 0; k < 9; ++k) {
    int pr = k, pc = k;
    double best = -1.0;
    for (int r = k; r < 10; ++r)
      for (int c = k; c < 10; ++c) {
        const double v = std::abs(A[r][c]);
        if (v > best) {
          best = v;
          pr = r;
          pc = c;
        }
      }
    if (!(best > 1e-14 * a_max)) return false;
    if (pr != k)
      for (int c = 0; c < 10; ++c) std::swap(A[pr][c], A[k][c]);
    if (pc != k) {
      for (int r = 0; r < 10; ++r) std::swap(A[r][pc], A[r][k]);
      std::swap(col_perm[pc], col_perm[k]);
    }
    const double inv = 1.0 / A[k][k];
    for (int r = k + 1; r < 10; ++r) {
      const double factor = A[r][k] * inv;
      for (int c = k + 1; c < 10; ++c) A[r][c] -= factor * A[k][c];
    }
  }
  // Back substitution in the leading 9x9 upper triangle with the last (permuted) component 1.
  double v[10];
  v[9] = 1.0;
  for (int k = 8; k >= 0; --k) {
    double s = A[k][9];
    for (int c = k + 1; c < 9; ++c) s += A[k][c] * v[c];
    v[k] = -s / A[k][k];
  }
  for (int i = 0; i < 10; ++i) (*z)[col_perm[i]] = v[i];
  return z->allFinite();
}

// Residual of the essential-matrix constraints of E = K F K (K = diag(f, f, 1), w = 1 / f^2),
// scale-invariant: max(|det E|, ||2 E E^T E - tr(E E^T) E||) for E normalised to unit norm.
double EssentialResidual(const Eigen::Matrix3d& F, double w) {
  const double f = 1.0 / std::sqrt(w);
  Eigen::Matrix3d E = F;
  E.topLeftCorner<2, 2>() *= f * f;
  E.topRightCorner<2, 1>() *= f;
  E.bottomLeftCorner<1, 2>() *= f;
  const double norm = E.norm();
  if (!(norm > 0.0) || !std::isfinite(norm)) return std::numeric_limits<double>::infinity();
  E /= norm;
  const Eigen::Matrix3d EEt = E * E.transpose();
  const double trace_residual = (2.0 * EEt * E - EEt.trace() * E).norm();
  return std::max(std::abs(E.determinant()), trace_residual);
}

}  // namespace

int SolveSharedFocal6pt(const std::vector<Eigen::Vector2d>& p0, const std::vector<Eigen::Vector2d>& p1,
                        std::vector<FocalFundamental>* solutions) {
  solutions->clear();
  if (p0.size() < 6 || p1.size() < 6) return 0;

  // Scale the coordinates to unit RMS radius (the principal point must stay at the origin).
  double sum_sq = 0.0;
  for (int i = 0; i < 6; ++i) sum_sq += p0[i].squaredNorm() + p1[i].squaredNorm();
  if (!std::isfinite(sum_sq) || !(sum_sq > 0.0)) return 0;
  const double scale = std::sqrt(sum_sq / 12.0);

  // Epipolar constraints q1^T F q0 = 0, F row-major in a 9-vector; null space from a QR of A^T.
  Eigen::Matrix<double, 9, 6> At;
  for (int i = 0; i < 6; ++i) {
    const Eigen::Vector3d q0(p0[i].x() / scale, p0[i].y() / scale, 1.0);
    const Eigen::Vector3d q1(p1[i].x() / scale, p1[i].y() / scale, 1.0);
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) At(3 * a + b, i) = q1[a] * q0[b];
  }
  const Eigen::ColPivHouseholderQR<Eigen::Matrix<double, 9, 6>> qr(At);
  const double r_max = std::abs(qr.matrixR()(0, 0));
  if (!(std::abs(qr.matrixR()(5, 5)) > 1e-12 * r_max)) return 0;  // fewer than 6 independent constraints
  const Eigen::Matrix<double, 9, 9> Qfull = qr.householderQ();
  const Eigen::Matrix<double, 9, 3> basis = Qfull.rightCols<3>();

  // F_ij = x * basis(k, 0) + y * basis(k, 1) + basis(k, 2), k = 3 i + j.
  Lin L[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) L[i][j] = basis.row(3 * i + j).transpose();

  // F^T Q F = N0 + w N1 (symmetric, quadratic entries).
  Quad N0[3][3], N1[3][3];
  for (int k = 0; k < 3; ++k)
    for (int j = k; j < 3; ++j) {
      N0[k][j] = N0[j][k] = Mul11(L[0][k], L[0][j]) + Mul11(L[1][k], L[1][j]);
      N1[k][j] = N1[j][k] = Mul11(L[2][k], L[2][j]);
    }
  // tr(F Q F^T Q) = tr0 + w tr1 + w^2 tr2.
  const Quad tr0 = N0[0][0] + N0[1][1];
  const Quad tr1 = N0[2][2] + N1[0][0] + N1[1][1];
  const Lin& f33 = L[2][2];

  Mat10 C0, C1;
  Eigen::Matrix<double, 10, 6> G;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const int r = 3 * i + j;
      // 2 F Q (F^T Q F) - tr(F Q F^T Q) F, split by powers of w.
      C0.row(r) = (2.0 * (Mul12(L[i][0], N0[0][j]) + Mul12(L[i][1], N0[1][j])) - Mul12(L[i][j], tr0)).transpose();
      C1.row(r) =
          (2.0 * (Mul12(L[i][0], N1[0][j]) + Mul12(L[i][1], N1[1][j]) + Mul12(L[i][2], N0[2][j])) - Mul12(L[i][j], tr1))
              .transpose();
      // w^2: 2 F_i3 F33 F_3j - F33^2 F_ij = F33 (2 F_i3 F_3j - F33 F_ij).
      G.row(r) = (2.0 * Mul11(L[i][2], L[2][j]) - Mul11(L[i][j], f33)).transpose();
    }
  // det(F) by cofactors of the first row (no w).
  const Quad c00 = Mul11(L[1][1], L[2][2]) - Mul11(L[1][2], L[2][1]);
  const Quad c01 = Mul11(L[1][2], L[2][0]) - Mul11(L[1][0], L[2][2]);
  const Quad c02 = Mul11(L[1][0], L[2][1]) - Mul11(L[1][1], L[2][0]);
  C0.row(9) = (Mul12(L[0][0], c00) + Mul12(L[0][1], c01) + Mul12(L[0][2], c02)).transpose();
  C1.row(9).setZero();
  G.row(9).setZero();
  Eigen::Matrix<double, 6, 10> H;
  for (int k = 0; k < 6; ++k) H.row(k) = Mul12(f33, Quad::Unit(k)).transpose();
  const Mat10 C2 = G * H;

  // Linearisation in mu = 1 / w.
  const Eigen::PartialPivLU<Mat10> lu(C0);
  Mat16 M;
  M.topLeftCorner<10, 10>() = -lu.solve(C1);
  M.topRightCorner<10, 6>() = -lu.solve(G);
  M.bottomLeftCorner<6, 10>() = H;
  M.bottomRightCorner<6, 6>().setZero();
  if (!M.allFinite()) return 0;
  // Eigenvalues mu = f^2 (in normalised units); the linearisation has one spurious eigenvalue mu = 0
  // (numerically about 1e-14).
  Mat16 hessenberg = Eigen::HessenbergDecomposition<Mat16>(M).matrixH();
  double lambda_real[16], lambda_imag[16];
  if (!HessenbergEigenvalues(hessenberg, lambda_real, lambda_imag)) return 0;
  // Real eigenvalues, and one of each nearly real complex pair (a real double root split by round-off;
  // the polishing below decides). mu below 1e-10 of the largest eigenvalue is the spurious zero
  // (a focal length below 1e-5 of the point spread would be meaningless anyway).
  double lambda_max = 0.0;
  for (int e = 0; e < 16; ++e) lambda_max = std::max(lambda_max, std::hypot(lambda_real[e], lambda_imag[e]));
  double roots[16];
  int num_roots = 0;
  for (int e = 0; e < 16; ++e) {
    const double re = lambda_real[e], im = lambda_imag[e];
    if (!(re > 1e-10 * lambda_max) || im < 0.0 || im > 1e-4 * re) continue;
    roots[num_roots++] = re;
  }

  solutions->reserve(kMaxSolutions);
  struct Candidate {
    double x, y, w, residual;
  };
  Candidate accepted[16];
  int num_accepted = 0;
  for (int e = 0; e < num_roots; ++e) {
    double w = 1.0 / roots[e];
    // Null vector of C0 + w C1 + w^2 C2 (rank 9 at a solution).
    Cubic m;
    if (!NullVector(C0 + w * C1 + (w * w) * C2, &m)) continue;
    // x, y from the ratio with the largest denominator.
    double x, y;
    if (std::abs(m[4]) > std::abs(m[9]) && std::abs(m[4]) > std::abs(m[7])) {
      x = m[0] / m[4];
    } else if (std::abs(m[7]) > std::abs(m[9])) {
      x = m[4] / m[7];
    } else {
      x = m[7] / m[9];
    }
    if (std::abs(m[6]) > std::abs(m[9]) && std::abs(m[6]) > std::abs(m[8])) {
      y = m[3] / m[6];
    } else if (std::abs(m[8]) > std::abs(m[9])) {
      y = m[6] / m[8];
    } else {
      y = m[8] / m[9];
    }
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(w)) continue;

    // Gauss-Newton polishing of (x, y, w) on (C0 + w C1 + w^2 C2) m(x, y) = 0.
    for (int iter = 0; iter < 8; ++iter) {
      Cubic mv, dmx, dmy;
      Monomials(x, y, &mv, &dmx, &dmy);
      const Mat10 Cw = C0 + w * C1 + (w * w) * C2;
      Eigen::Matrix<double, 10, 3> J;
      J.col(0).noalias() = Cw * dmx;
      J.col(1).noalias() = Cw * dmy;
      J.col(2).noalias() = C1 * mv + (2.0 * w) * (C2 * mv);
      const Cubic res = Cw * mv;
      const Eigen::Matrix3d JtJ = J.transpose() * J;
      const Eigen::Vector3d delta = JtJ.ldlt().solve(-J.transpose() * res);
      if (!delta.allFinite()) break;
      x += delta[0];
      y += delta[1];
      w += delta[2];
      if (std::abs(delta[0]) + std::abs(delta[1]) <= 1e-14 * (1.0 + std::abs(x) + std::abs(y)) &&
          std::abs(delta[2]) <= 1e-14 * std::abs(w))
        break;
    }
    if (!(w > 0.0) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(w)) continue;

    Eigen::Matrix3d Fn;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) Fn(i, j) = L[i][j].dot(Eigen::Vector3d(x, y, 1.0));
    const double residual = EssentialResidual(Fn, w);
    if (!(residual < 1e-9)) continue;

    bool duplicate = false;
    for (int k = 0; k < num_accepted && !duplicate; ++k) {
      const Candidate& c = accepted[k];
      duplicate = std::abs(c.x - x) + std::abs(c.y - y) <= 1e-8 * (1.0 + std::abs(x) + std::abs(y)) &&
                  std::abs(c.w - w) <= 1e-8 * w;
    }
    if (duplicate) continue;
    accepted[num_accepted++] = {x, y, w, residual};
  }

  // More than 15 can only come from numerical noise: keep the 15 with the smallest residual.
  if (num_accepted > kMaxSolutions) {
    std::sort(accepted, accepted + num_accepted,
              [](const Candidate& a, const Candidate& b) { return a.residual < b.residual; });
    num_accepted = kMaxSolutions;
  }

  const Eigen::Vector3d unscale(1.0 / scale, 1.0 / scale, 1.0);
  for (int k = 0; k < num_accepted; ++k) {
    const Candidate& c = accepted[k];
    Eigen::Matrix3d F;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) F(i, j) = L[i][j].dot(Eigen::Vector3d(c.x, c.y, 1.0)) * unscale[i] * unscale[j];
    const double norm = F.norm();
    if (!(norm > 0.0) || !std::isfinite(norm)) continue;
    FocalFundamental sol;
    sol.F = F / norm;
    sol.f0 = sol.f1 = scale / std::sqrt(c.w);
    solutions->push_back(sol);
  }
  return static_cast<int>(solutions->size());
}

}  // namespace madsfm
