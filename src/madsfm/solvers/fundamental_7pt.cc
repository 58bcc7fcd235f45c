#include "madsfm/solvers/fundamental_7pt.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "madsfm/geometry/portable_math.h"

namespace madsfm {
namespace {

// Hartley-style normalisation of 7 points: centroid to the origin, RMS distance sqrt(2).
// Returns false for coincident or non-finite points.
bool Normalize7(const std::vector<Eigen::Vector2d>& p, Eigen::Vector2d q[7], double* scale, Eigen::Vector2d* centre) {
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (int i = 0; i < 7; ++i) c += p[i];
  c /= 7.0;
  double sq = 0.0;
  for (int i = 0; i < 7; ++i) {
    q[i] = p[i] - c;
    sq += q[i].squaredNorm();
  }
  if (!std::isfinite(sq) || !(sq > 0.0)) return false;
  const double s = std::sqrt(14.0 / sq);  // sqrt(2) / sqrt(sq / 7)
  for (int i = 0; i < 7; ++i) q[i] *= s;
  *scale = s;
  *centre = c;
  return true;
}

// The 2-dimensional null space of the 7x9 matrix A (row-major, a[9 * r + c]) by Gauss-Jordan
// elimination with column pivoting (partial pivoting on A^T). Writes two independent null
// vectors; returns false when rank(A) < 7.
bool NullSpace7x9(double a[63], Eigen::Matrix<double, 9, 1>* n0, Eigen::Matrix<double, 9, 1>* n1) {
  int col_of[9] = {0, 1, 2, 3, 4, 5, 6, 7, 8};  // column permutation
  double row_scale[7];
  for (int r = 0; r < 7; ++r) {
    double m = 0.0;
    for (int c = 0; c < 9; ++c) m = std::max(m, std::abs(a[9 * r + c]));
    row_scale[r] = m;
  }
  for (int k = 0; k < 7; ++k) {
    double* row_k = a + 9 * k;
    int pc = k;
    double best = std::abs(row_k[k]);
    for (int c = k + 1; c < 9; ++c) {
      const double v = std::abs(row_k[c]);
      if (v > best) {
        best = v;
        pc = c;
      }
    }
    // A row (almost) in the span of the previous ones: rank < 7, F is not determined.
    if (!(best > 1e-10 * row_scale[k])) return false;
    if (pc != k) {
      for (int r = 0; r < 7; ++r) std::swap(a[9 * r + k], a[9 * r + pc]);
      std::swap(col_of[k], col_of[pc]);
    }
    const double inv = 1.0 / row_k[k];
    for (int c = k; c < 9; ++c) row_k[c] *= inv;
    for (int r = 0; r < 7; ++r) {
      if (r == k) continue;
      double* row_r = a + 9 * r;
      const double f = row_r[k];
      for (int c = k; c < 9; ++c) row_r[c] -= f * row_k[c];
    }
  }
  // A = [I | B] in the permuted columns: the null vectors are [-B.col(j); e_j].
  for (int r = 0; r < 7; ++r) {
    (*n0)(col_of[r]) = -a[9 * r + 7];
    (*n1)(col_of[r]) = -a[9 * r + 8];
  }
  (*n0)(col_of[7]) = 1.0;
  (*n1)(col_of[8]) = 1.0;
  (*n0)(col_of[8]) = 0.0;
  (*n1)(col_of[7]) = 0.0;
  return true;
}

// Cofactor matrix (adjugate transposed) of a 3x3 matrix.
Eigen::Matrix3d Cofactor(const Eigen::Matrix3d& M) {
  Eigen::Matrix3d C;
  C.col(0) = M.col(1).cross(M.col(2));
  C.col(1) = M.col(2).cross(M.col(0));
  C.col(2) = M.col(0).cross(M.col(1));
  return C;
}

// Real roots of c3 x^3 + c2 x^2 + c1 x + c0 with c3 != 0 (closed form, then Newton-polished).
int SolveCubic(double c3, double c2, double c1, double c0, double roots[3]) {
  const double a = c2 / c3, b = c1 / c3, c = c0 / c3;
  // Depressed cubic y^3 + p y + q with x = y - a / 3.
  const double a3 = a / 3.0;
  const double p = b - a * a3;
  const double q = c - b * a3 + 2.0 * a3 * a3 * a3;
  const double h = 0.25 * q * q + p * p * p / 27.0;
  int n = 0;
  if (h > 0.0) {
    // One real root (Cardano, in the cancellation-free form).
    const double s = std::sqrt(h);
    const double u = std::cbrt(-0.5 * q + (q > 0.0 ? -s : s));
    roots[n++] = (u != 0.0 ? u - p / (3.0 * u) : 0.0) - a3;
  } else {
    // Three real roots (trigonometric form); p <= 0 here.
    const double m = std::sqrt(std::max(-p / 3.0, 0.0));
    if (m == 0.0) {
      roots[n++] = -a3;
    } else {
      const double arg = std::max(-1.0, std::min(1.0, -0.5 * q / (m * m * m)));
      const double phi = portable::Acos(arg) / 3.0;  // not <cmath>: same bits on every CPU
      roots[n++] = 2.0 * m * portable::Cos(phi) - a3;
      roots[n++] = 2.0 * m * portable::Cos(phi - 2.0 * M_PI / 3.0) - a3;
      roots[n++] = 2.0 * m * portable::Cos(phi + 2.0 * M_PI / 3.0) - a3;
    }
  }
  for (int i = 0; i < n; ++i) {
    double x = roots[i];
    for (int it = 0; it < 3; ++it) {
      const double f = ((x + a) * x + b) * x + c;
      const double df = (3.0 * x + 2.0 * a) * x + b;
      if (df == 0.0) break;
      const double nx = x - f / df;
      if (!std::isfinite(nx)) break;
      // Keep the step only if it does not make the residual worse.
      const double nf = ((nx + a) * nx + b) * nx + c;
      if (std::abs(nf) > std::abs(f)) break;
      x = nx;
      if (nf == 0.0) break;
    }
    roots[i] = x;
  }
  return n;
}

}  // namespace

int SolveFundamental7pt(const std::vector<Eigen::Vector2d>& p0, const std::vector<Eigen::Vector2d>& p1,
                        std::vector<Eigen::Matrix3d>* fundamentals) {
  fundamentals->clear();
  fundamentals->reserve(3);
  if (p0.size() < 7 || p1.size() < 7) return 0;

  Eigen::Vector2d q0[7], q1[7], c0, c1;
  double s0, s1;
  if (!Normalize7(p0, q0, &s0, &c0) || !Normalize7(p1, q1, &s1, &c1)) return 0;

  // Row i: the coefficients of vec(F) (row-major) in [q1;1]^T F [q0;1] = 0.
  double a[63];
  for (int i = 0; i < 7; ++i) {
    const double x0 = q0[i].x(), y0 = q0[i].y(), x1 = q1[i].x(), y1 = q1[i].y();
    double* row = a + 9 * i;
    row[0] = x1 * x0;
    row[1] = x1 * y0;
    row[2] = x1;
    row[3] = y1 * x0;
    row[4] = y1 * y0;
    row[5] = y1;
    row[6] = x0;
    row[7] = y0;
    row[8] = 1.0;
  }
  Eigen::Matrix<double, 9, 1> n0, n1;
  if (!NullSpace7x9(a, &n0, &n1)) return 0;
  // Orthonormalise the basis (Gram-Schmidt) to keep the cubic well conditioned.
  n0.normalize();
  n1 -= n1.dot(n0) * n0;
  const double n1_norm = n1.norm();
  if (!(n1_norm > 1e-12)) return 0;
  n1 /= n1_norm;
  const Eigen::Matrix3d F0 = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(n0.data());
  const Eigen::Matrix3d F1 = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(n1.data());

  // det(x F0 + y F1) = d0 x^3 + k1 x^2 y + k2 x y^2 + d1 y^3.
  const Eigen::Matrix3d C0 = Cofactor(F0), C1 = Cofactor(F1);
  const double d0 = F0.col(0).dot(C0.col(0));
  const double d1 = F1.col(0).dot(C1.col(0));
  const double k1 = C0.cwiseProduct(F1).sum();
  const double k2 = C1.cwiseProduct(F0).sum();

  // Dehomogenise on the side with the larger leading coefficient: F = F0 + y F1 (roots y of
  // d1 y^3 + k2 y^2 + k1 y + d0) or F = x F0 + F1 (roots x of d0 x^3 + k1 x^2 + k2 x + d1).
  const bool along_f1 = std::abs(d1) >= std::abs(d0);
  double roots[3];
  int num_roots = 0;
  bool add_endpoint = false;
  if (along_f1 ? d1 != 0.0 : d0 != 0.0) {
    num_roots = along_f1 ? SolveCubic(d1, k2, k1, d0, roots) : SolveCubic(d0, k1, k2, d1, roots);
  } else {
    // d0 = d1 = 0: det = x y (k1 x + k2 y). F0 (y = 0) and F1 (x = 0) are solutions, and with
    // x = 1 the third root is y = -k1 / k2. A pencil of singular matrices (k1 = k2 = 0) gives none.
    if (k1 != 0.0 || k2 != 0.0) {
      roots[num_roots++] = 0.0;
      if (k2 != 0.0) roots[num_roots++] = -k1 / k2;
      add_endpoint = true;
    }
  }

  // Undo the normalisation on the basis (F is linear in it): [q;1] = T [p;1] with
  // T = [s I, -s c; 0, 1], so F = T1^T Fn T0.
  const auto denormalize = [&](const Eigen::Matrix3d& Fn) {
    Eigen::Matrix3d G;
    // Fn T0: columns 0, 1 scale by s0, column 2 gets -s0 (c0.x col0 + c0.y col1) + col2.
    G.col(0) = s0 * Fn.col(0);
    G.col(1) = s0 * Fn.col(1);
    G.col(2) = Fn.col(2) - c0.x() * G.col(0) - c0.y() * G.col(1);
    // T1^T (.): rows 0, 1 scale by s1, row 2 gets -s1 (c1.x row0 + c1.y row1) + row2.
    G.row(0) *= s1;
    G.row(1) *= s1;
    G.row(2) -= c1.x() * G.row(0) + c1.y() * G.row(1);
    return G;
  };
  const Eigen::Matrix3d G0 = denormalize(F0), G1 = denormalize(F1);

  auto emit = [&](const Eigen::Matrix3d& F) {
    const double norm = F.norm();
    if (!(norm > 0.0) || !std::isfinite(norm)) return;
    fundamentals->push_back(F / norm);
  };
  for (int i = 0; i < num_roots; ++i) {
    if (!std::isfinite(roots[i])) continue;
    if (along_f1 || add_endpoint) {
      emit(G0 + roots[i] * G1);
    } else {
      emit(roots[i] * G0 + G1);
    }
  }
  if (add_endpoint) emit(G1);
  return static_cast<int>(fundamentals->size());
}

}  // namespace madsfm
