#include "madsfm/solvers/hessenberg_eigenvalues.h"

#include <algorithm>
#include <cmath>

namespace madsfm {
namespace {

constexpr double kEps = 2.220446049250313e-16;

// Eigenvalues of [[a, b], [c, d]]: (re0, im0) and (re1, im1), im0 >= 0 >= im1 for a complex pair.
void Eigenvalues2x2(double a, double b, double c, double d, double* re0, double* im0, double* re1, double* im1) {
  const double p = 0.5 * (a - d);
  const double q = p * p + b * c;
  if (q >= 0.0) {
    // d + p +- sqrt(q), the smaller one from the product (no cancellation).
    const double z = p + std::copysign(std::sqrt(q), p);
    *re0 = d + z;
    *re1 = z != 0.0 ? d - (b / z) * c : d + z;
    *im0 = *im1 = 0.0;
  } else {
    *re0 = *re1 = d + p;
    *im0 = std::sqrt(-q);
    *im1 = -*im0;
  }
}

// Householder reflector I - beta v v^T with v = (1, v1, v2) mapping (x, y, z) to (alpha, 0, 0).
// Returns false when (y, z) is already zero (no reflection needed).
bool Reflector3(double x, double y, double z, double* v1, double* v2, double* beta, double* alpha) {
  const double tail = y * y + z * z;
  if (tail == 0.0) return false;
  const double norm = std::sqrt(x * x + tail);
  *alpha = x > 0.0 ? -norm : norm;
  const double v0 = x - *alpha;
  *v1 = y / v0;
  *v2 = z / v0;
  *beta = 2.0 / (1.0 + *v1 * *v1 + *v2 * *v2);
  return true;
}

}  // namespace

bool HessenbergEigenvalues(Eigen::Ref<Eigen::MatrixXd> H, double* real, double* imag) {
  const int n = static_cast<int>(H.rows());
  if (n < 1 || n > kMaxHessenbergOrder || H.cols() != n) return false;
  double norm = 0.0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i <= std::min(j + 1, n - 1); ++i) norm += std::abs(H(i, j));
  if (!std::isfinite(norm)) return false;
  if (norm == 0.0) {
    for (int k = 0; k < n; ++k) real[k] = imag[k] = 0.0;
    return true;
  }

  int iu = n - 1;  // last row of the active block
  int iterations = 0, total_iterations = 0;
  while (iu >= 0) {
    // Start of the unreduced block ending at iu: the lowest l with a negligible H(l, l - 1).
    int l = iu;
    for (; l > 0; --l) {
      double s = std::abs(H(l - 1, l - 1)) + std::abs(H(l, l));
      if (s == 0.0) s = norm;
      if (std::abs(H(l, l - 1)) <= kEps * s) {
        H(l, l - 1) = 0.0;
        break;
      }
    }
    if (l == iu) {  // a 1 x 1 block
      real[iu] = H(iu, iu);
      imag[iu] = 0.0;
      --iu;
      iterations = 0;
      continue;
    }
    if (l == iu - 1) {  // a 2 x 2 block
      Eigenvalues2x2(H(iu - 1, iu - 1), H(iu - 1, iu), H(iu, iu - 1), H(iu, iu), &real[iu - 1], &imag[iu - 1],
                     &real[iu], &imag[iu]);
      iu -= 2;
      iterations = 0;
      continue;
    }
    if (++total_iterations > 30 * n) return false;
    ++iterations;

    // Shifts: the eigenvalues of the trailing 2 x 2 block (sum s, product t), or ad hoc ones at every
    // 10th step without deflation (they break the rare cycles of the standard shifts).
    double s, t;
    if (iterations % 10 == 0) {
      const double e = std::abs(H(iu, iu - 1)) + std::abs(H(iu - 1, iu - 2));
      const double centre = H(iu, iu) + 0.75 * e;
      s = 2.0 * centre;
      t = centre * centre + 0.4375 * e * e;
    } else {
      s = H(iu - 1, iu - 1) + H(iu, iu);
      t = H(iu - 1, iu - 1) * H(iu, iu) - H(iu - 1, iu) * H(iu, iu - 1);
    }
    // First column of (H - s1 I)(H - s2 I) = H^2 - s H + t I.
    double x = H(l, l) * H(l, l) + H(l, l + 1) * H(l + 1, l) - s * H(l, l) + t;
    double y = H(l + 1, l) * (H(l, l) + H(l + 1, l + 1) - s);
    double z = H(l + 1, l) * H(l + 2, l + 1);
    // Chase the bulge down the block with 3 x 3 reflectors, then one 2 x 2 reflector.
    for (int k = l; k <= iu - 1; ++k) {
      const bool last = k == iu - 1;
      double v1, v2, beta, alpha;
      if (!Reflector3(x, y, last ? 0.0 : z, &v1, &v2, &beta, &alpha)) {
        if (!last) {
          x = H(k + 1, k);
          y = H(k + 2, k);
          if (k + 3 <= iu) z = H(k + 3, k);
        }
        continue;
      }
      const int rows = last ? 2 : 3;
      // From the left: rows k .. k + rows - 1, columns from max(l, k - 1) to iu.
      const int c0 = std::max(l, k - 1);
      for (int j = c0; j <= iu; ++j) {
        double w = H(k, j) + v1 * H(k + 1, j);
        if (rows == 3) w += v2 * H(k + 2, j);
        w *= beta;
        H(k, j) -= w;
        H(k + 1, j) -= w * v1;
        if (rows == 3) H(k + 2, j) -= w * v2;
      }
      if (k > l) {
        H(k, k - 1) = alpha;
        H(k + 1, k - 1) = 0.0;
        if (rows == 3) H(k + 2, k - 1) = 0.0;
      }
      // From the right: columns k .. k + rows - 1, rows l .. min(k + 3, iu).
      const int r1 = std::min(k + 3, iu);
      for (int i = l; i <= r1; ++i) {
        double w = H(i, k) + v1 * H(i, k + 1);
        if (rows == 3) w += v2 * H(i, k + 2);
        w *= beta;
        H(i, k) -= w;
        H(i, k + 1) -= w * v1;
        if (rows == 3) H(i, k + 2) -= w * v2;
      }
      if (!last) {
        x = H(k + 1, k);
        y = H(k + 2, k);
        if (k + 3 <= iu) z = H(k + 3, k);
      }
    }
  }
  for (int k = 0; k < n; ++k)
    if (!std::isfinite(real[k]) || !std::isfinite(imag[k])) return false;
  return true;
}

}  // namespace madsfm
