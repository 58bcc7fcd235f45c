// Eigenvalues (without eigenvectors) of a small real upper Hessenberg matrix, for the solvers whose
// last step is an eigenvalue problem (shared_focal_6pt).
#pragma once

#include <Eigen/Core>

namespace madsfm {

// Largest order HessenbergEigenvalues accepts.
inline constexpr int kMaxHessenbergOrder = 32;

// Computes all eigenvalues of the upper Hessenberg matrix H (n x n, 1 <= n <= kMaxHessenbergOrder;
// entries below the first subdiagonal are ignored). H is overwritten.
// - Method: Francis double-shift QR iterations (Golub and Van Loan, "Matrix Computations",
//   Algorithm 7.5.1) with deflation at negligible subdiagonal entries. Only the unreduced block is
//   updated (the Schur form is not needed), which is what makes it several times faster than a
//   full real Schur decomposition for the 16 x 16 matrices of the solvers.
// - Eigenvalue k is real[k] + i imag[k]; complex pairs are stored next to each other, the one with
//   positive imaginary part first. The order is otherwise unspecified.
// - Returns false (and leaves the output unspecified) if n is out of range, H is not finite, or the
//   iteration does not converge within 30 n double steps.
bool HessenbergEigenvalues(Eigen::Ref<Eigen::MatrixXd> H, double* real, double* imag);

}  // namespace madsfm
