#include "madsfm/refinement/relpose_refiner.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <cmath>
#include <limits>

#include "madsfm/geometry/essential_matrix.h"
#include "madsfm/geometry/portable_math.h"

namespace madsfm {
namespace {

using Vector11d = Eigen::Matrix<double, kRelposeNumParams, 1>;
using Matrix11d = Eigen::Matrix<double, kRelposeNumParams, kRelposeNumParams>;
using Row11d = Eigen::Matrix<double, 1, kRelposeNumParams>;

enum Param { kRot = 0, kTrans = 3, kShift0 = 6, kShift1 = 7, kScale = 8, kF0 = 9, kF1 = 10 };

// Evaluates every residual and (optionally) its Jacobian row, calling sink(residual, row) for each.
template <bool kWithJacobian, typename Sink>
bool ForEachResidual(const RelposeProblem& p, const std::vector<int>& I0, const std::vector<int>& I1,
                     const std::vector<int>& Is, double sampson_weight, const AffineDepthPose& m, Sink&& sink,
                     double reprojection_weight = 1.0) {
  const Eigen::Matrix3d& R = m.R;
  const Eigen::Matrix3d Rt = R.transpose();
  const double f0 = m.f0, f1 = m.f1;
  const double rw = std::sqrt(reprojection_weight);
  const double ps0 = p.pixel_scale0 * rw, ps1 = p.pixel_scale1 * rw;
  Row11d row0, row1;

  for (int i : I0) {
    const Eigen::Vector2d& x0 = p.x0[i];
    const Eigen::Vector2d& x1 = p.x1[i];
    const double z0 = p.d0[i] + m.shift0;
    const Eigen::Vector3d v0(x0.x() / f0, x0.y() / f0, 1.0);
    const Eigen::Vector3d Y = R * (z0 * v0);
    const Eigen::Vector3d X1 = Y + m.t;
    if (!(z0 > 0.0) || !(X1.z() > 0.0)) return false;
    const double iz = 1.0 / X1.z();
    const double u = X1.x() * iz, v = X1.y() * iz;
    const double rx = ps1 * (f1 * u - x1.x()), ry = ps1 * (f1 * v - x1.y());
    if constexpr (kWithJacobian) {
      Eigen::Matrix<double, 2, 3> A;
      const double k = ps1 * f1 * iz;
      A << k, 0.0, -k * u, 0.0, k, -k * v;
      // dX1/dw = -[Y]x
      Eigen::Matrix3d dX_dw;
      dX_dw << 0.0, Y.z(), -Y.y(), -Y.z(), 0.0, Y.x(), Y.y(), -Y.x(), 0.0;
      const Eigen::Matrix<double, 2, 3> Jw = A * dX_dw;
      const Eigen::Vector2d Js0 = A * (R * v0);
      const Eigen::Vector2d Jf0 = A * (R * Eigen::Vector3d(-z0 * x0.x() / (f0 * f0), -z0 * x0.y() / (f0 * f0), 0.0));
      row0.setZero();
      row1.setZero();
      row0.segment<3>(kRot) = Jw.row(0);
      row1.segment<3>(kRot) = Jw.row(1);
      row0.segment<3>(kTrans) = A.row(0);
      row1.segment<3>(kTrans) = A.row(1);
      row0(kShift0) = Js0(0);
      row1(kShift0) = Js0(1);
      row0(kF0) = Jf0(0);
      row1(kF0) = Jf0(1);
      row0(kF1) = ps1 * u;
      row1(kF1) = ps1 * v;
    }
    sink(rx, row0);
    sink(ry, row1);
  }

  for (int i : I1) {
    const Eigen::Vector2d& x0 = p.x0[i];
    const Eigen::Vector2d& x1 = p.x1[i];
    const double dd = p.d1[i] + m.shift1;
    const double z1 = m.scale * dd;
    const Eigen::Vector3d v1(x1.x() / f1, x1.y() / f1, 1.0);
    const Eigen::Vector3d W = z1 * v1 - m.t;
    const Eigen::Vector3d X0 = Rt * W;
    if (!(z1 > 0.0) || !(X0.z() > 0.0)) return false;
    const double iz = 1.0 / X0.z();
    const double u = X0.x() * iz, v = X0.y() * iz;
    const double rx = ps0 * (f0 * u - x0.x()), ry = ps0 * (f0 * v - x0.y());
    if constexpr (kWithJacobian) {
      Eigen::Matrix<double, 2, 3> B;
      const double k = ps0 * f0 * iz;
      B << k, 0.0, -k * u, 0.0, k, -k * v;
      const Eigen::Matrix<double, 2, 3> BRt = B * Rt;
      // dX0/dw = R^T [W]x
      Eigen::Matrix3d Wx;
      Wx << 0.0, -W.z(), W.y(), W.z(), 0.0, -W.x(), -W.y(), W.x(), 0.0;
      const Eigen::Matrix<double, 2, 3> Jw = BRt * Wx;
      const Eigen::Vector2d Js1 = BRt * (m.scale * v1);
      const Eigen::Vector2d Ja = BRt * (dd * v1);
      const Eigen::Vector2d Jf1 = BRt * Eigen::Vector3d(-z1 * x1.x() / (f1 * f1), -z1 * x1.y() / (f1 * f1), 0.0);
      row0.setZero();
      row1.setZero();
      row0.segment<3>(kRot) = Jw.row(0);
      row1.segment<3>(kRot) = Jw.row(1);
      row0.segment<3>(kTrans) = -BRt.row(0);
      row1.segment<3>(kTrans) = -BRt.row(1);
      row0(kShift1) = Js1(0);
      row1(kShift1) = Js1(1);
      row0(kScale) = Ja(0);
      row1(kScale) = Ja(1);
      row0(kF1) = Jf1(0);
      row1(kF1) = Jf1(1);
      row0(kF0) = ps0 * u;
      row1(kF0) = ps0 * v;
    }
    sink(rx, row0);
    sink(ry, row1);
  }

  if (!Is.empty()) {
    const Eigen::Matrix3d tx = CrossProductMatrix(m.t);
    const Eigen::Matrix3d E = tx * R;
    const double k = std::sqrt(sampson_weight * p.pixel_scale0 * p.pixel_scale1);
    const double if0 = 1.0 / f0, if1 = 1.0 / f1;
    for (int i : Is) {
      const Eigen::Vector3d y0(p.x0[i].x() * if0, p.x0[i].y() * if0, 1.0);
      const Eigen::Vector3d y1(p.x1[i].x() * if1, p.x1[i].y() * if1, 1.0);
      const Eigen::Vector3d a = E * y0;
      const Eigen::Vector3d b = E.transpose() * y1;
      const double c = y1.dot(a);
      const double na = a.x() * a.x() + a.y() * a.y(), nb = b.x() * b.x() + b.y() * b.y();
      const double D = na * if1 * if1 + nb * if0 * if0;
      if (!(D > 0.0)) return false;
      const double sD = std::sqrt(D);
      const double e = k * c / sD;
      if constexpr (kWithJacobian) {
        row0.setZero();
        const double g = k / sD, h = -k * c / (2.0 * D * sD);  // de = g dc + h dD
        // Rotation (R <- exp([w]x) R) and translation, in closed form with q = R y0, s = y1 x t,
        // alpha = 2/f1^2 (a_x, a_y, 0), gamma = R 2/f0^2 (b_x, b_y, 0):
        //   dc/dw = q x s,                      dc/dt = q x y1,
        //   dD/dw = q x (alpha x t) + gamma x s, dD/dt = q x alpha + gamma x y1.
        const Eigen::Vector3d q = R * y0;
        const Eigen::Vector3d s = y1.cross(m.t);
        const Eigen::Vector3d alpha(2.0 * a.x() * if1 * if1, 2.0 * a.y() * if1 * if1, 0.0);
        const Eigen::Vector3d gamma = R * Eigen::Vector3d(2.0 * b.x() * if0 * if0, 2.0 * b.y() * if0 * if0, 0.0);
        const Eigen::Vector3d Jw = g * q.cross(s) + h * (q.cross(alpha.cross(m.t)) + gamma.cross(s));
        const Eigen::Vector3d Jt = g * q.cross(y1) + h * (q.cross(alpha) + gamma.cross(y1));
        row0.segment<3>(kRot) = Jw.transpose();
        row0.segment<3>(kTrans) = Jt.transpose();
        // Focal lengths: dy0/df0 = (-x0/f0^2, -y0/f0^2, 0), likewise view 1.
        const Eigen::Vector3d dy0(-y0.x() * if0, -y0.y() * if0, 0.0);
        const Eigen::Vector3d dy1(-y1.x() * if1, -y1.y() * if1, 0.0);
        {
          const Eigen::Vector3d da = E * dy0;
          const double dc = b.dot(dy0);
          const double dD = 2.0 * (a.x() * da.x() + a.y() * da.y()) * if1 * if1 - 2.0 * nb * if0 * if0 * if0;
          row0(kF0) = g * dc + h * dD;
        }
        {
          const Eigen::Vector3d db = E.transpose() * dy1;
          const double dc = a.dot(dy1);
          const double dD = 2.0 * (b.x() * db.x() + b.y() * db.y()) * if0 * if0 - 2.0 * na * if1 * if1 * if1;
          row0(kF1) = g * dc + h * dD;
        }
      }
      sink(e, row0);
    }
  }
  return true;
}

AffineDepthPose ApplyStep(const AffineDepthPose& m, const Vector11d& d, bool shared_focal) {
  AffineDepthPose n = m;  // d is in the original parameters (the basis change is undone by the caller)
  const Eigen::Vector3d w = d.segment<3>(kRot);
  const double angle = w.norm();
  // Rodrigues with madsfm::portable's sin / cos (Eigen::AngleAxisd calls libm, whose result depends on the CPU).
  if (angle > 0.0) {
    double s, c;
    portable::SinCos(angle, &s, &c);
    const Eigen::Vector3d a = w / angle;
    Eigen::Matrix3d K;
    K << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
    const Eigen::Matrix3d step = Eigen::Matrix3d::Identity() + s * K + (1.0 - c) * (K * K);
    n.R = step * m.R;
  }
  n.t = m.t + d.segment<3>(kTrans);
  n.shift0 = m.shift0 + d(kShift0);
  n.shift1 = m.shift1 + d(kShift1);
  n.scale = m.scale + d(kScale);
  if (shared_focal) {
    n.f0 = n.f1 = m.f0 + d(kF0);
  } else {
    n.f0 = m.f0 + d(kF0);
    n.f1 = m.f1 + d(kF1);
  }
  return n;
}

}  // namespace

void EvaluateRelposeResiduals(const RelposeProblem& p, const std::vector<int>& I0, const std::vector<int>& I1,
                              const std::vector<int>& Is, double sampson_weight, const AffineDepthPose& model,
                              std::vector<double>* residuals, std::vector<std::vector<double>>* jacobian) {
  residuals->clear();
  if (jacobian) jacobian->clear();
  ForEachResidual<true>(p, I0, I1, Is, sampson_weight, model, [&](double r, const Row11d& row) {
    residuals->push_back(r);
    if (jacobian) jacobian->emplace_back(row.data(), row.data() + kRelposeNumParams);
  });
}

bool RefineRelpose(const RelposeProblem& p, const std::vector<int>& I0, const std::vector<int>& I1,
                   const std::vector<int>& Is, const RelposeRefinerOptions& options, AffineDepthPose* model,
                   RelposeRefinerSummary* summary) {
  const bool shared = p.mode == CameraMode::kSharedFocal;
  // Which parameters are free.
  bool free_param[kRelposeNumParams];
  for (int j = 0; j < 6; ++j) free_param[j] = true;
  const bool depth = options.refine_depth && options.reprojection_weight > 0.0 && (!I0.empty() || !I1.empty());
  free_param[kShift0] = depth && options.refine_shift && !I0.empty();
  free_param[kShift1] = depth && options.refine_shift && !I1.empty();
  free_param[kScale] = depth && !I1.empty();
  free_param[kF0] = options.refine_focal && p.mode != CameraMode::kCalibrated;
  free_param[kF1] = options.refine_focal && p.mode == CameraMode::kTwoFocal;
  // Parameter basis: identity, except that with a fixed pose the rotation is fixed and the translation moves
  // only along its direction (one parameter, in column kTrans).
  Matrix11d B = Matrix11d::Identity();
  if (!options.refine_pose) {
    const double tn = model->t.norm();
    if (!(tn > 0.0)) return false;
    for (int j = 0; j < 3; ++j) free_param[kRot + j] = false;
    free_param[kTrans + 1] = free_param[kTrans + 2] = false;
    B.block<3, 3>(kTrans, kTrans).setZero();
    B.block<3, 1>(kTrans, kTrans) = model->t / tn;
  }
  int num_free = 0;
  for (bool b : free_param) num_free += b;
  // Columns of J that enter the normal equations: the free parameters, and all three translation columns when the
  // basis B mixes them. With a shared focal length, f1's column is added to f0's (one parameter).
  int accumulated[kRelposeNumParams];
  int num_accumulated = 0, shared_f1_slot = -1;
  for (int j = 0; j < kRelposeNumParams; ++j) {
    if (free_param[j] || (!options.refine_pose && j >= kTrans && j < kTrans + 3)) {
      if (shared && j == kF0) shared_f1_slot = num_accumulated;
      accumulated[num_accumulated++] = j;
    }
  }
  const int num_residuals = 2 * static_cast<int>(I0.size() + I1.size()) + static_cast<int>(Is.size());
  if (num_residuals < num_free) return false;

  const double s2 = options.cauchy_scale * options.cauchy_scale;
  const bool robust = options.cauchy_scale > 0.0;
  auto loss = [&](double r2) { return robust ? s2 * portable::Log(1.0 + r2 / s2) : r2; };
  auto cost_of = [&](const AffineDepthPose& m, double* cost) {
    double c = 0.0;
    const bool ok = ForEachResidual<false>(
        p, I0, I1, Is, options.sampson_weight, m, [&](double r, const Row11d&) { c += loss(r * r); },
        options.reprojection_weight);
    *cost = c;
    return ok && std::isfinite(c);
  };

  AffineDepthPose current = *model;
  double cost;
  if (!cost_of(current, &cost)) return false;
  if (summary) summary->initial_cost = cost;
  double lambda = 1e-4;
  int it = 0;
  for (; it < options.max_iterations; ++it) {
    // Normal equations over the accumulated columns only, lower triangle, one row at a time (for these 11-column
    // rows this beats Eigen's blocked matrix products, which are tuned for large matrices).
    double lower[kRelposeNumParams][kRelposeNumParams] = {};
    double gradient[kRelposeNumParams] = {};
    ForEachResidual<true>(p, I0, I1, Is, options.sampson_weight, current, [&](double r, const Row11d& row) {
      const double sw = robust ? 1.0 / std::sqrt(1.0 + r * r / s2) : 1.0;  // sqrt of the IRLS weight
      double c[kRelposeNumParams];
      for (int a = 0; a < num_accumulated; ++a) c[a] = sw * row(accumulated[a]);
      if (shared_f1_slot >= 0) c[shared_f1_slot] += sw * row(kF1);
      const double wr = sw * r;
      for (int a = 0; a < num_accumulated; ++a) {
        const double ca = c[a];
        for (int b = 0; b <= a; ++b) lower[a][b] += ca * c[b];
        gradient[a] += ca * wr;
      }
    }, options.reprojection_weight);
    Matrix11d JtJ = Matrix11d::Zero();
    Vector11d Jtr = Vector11d::Zero();
    for (int a = 0; a < num_accumulated; ++a) {
      for (int b = 0; b <= a; ++b) JtJ(accumulated[a], accumulated[b]) = lower[a][b];
      Jtr(accumulated[a]) = gradient[a];
    }
    JtJ.triangularView<Eigen::StrictlyUpper>() = JtJ.transpose();
    if (!options.refine_pose) {
      JtJ = (B.transpose() * JtJ * B).eval();
      Jtr = (B.transpose() * Jtr).eval();
    }
    for (int j = 0; j < kRelposeNumParams; ++j) {
      if (!free_param[j]) {
        JtJ.row(j).setZero();
        JtJ.col(j).setZero();
        JtJ(j, j) = 1.0;
        Jtr(j) = 0.0;
      }
    }
    bool improved = false;
    double new_cost = cost;
    for (int attempt = 0; attempt < 10; ++attempt) {
      Matrix11d A = JtJ;
      for (int j = 0; j < kRelposeNumParams; ++j) A(j, j) += lambda * std::max(JtJ(j, j), 1e-12);
      const Vector11d delta_basis = A.ldlt().solve(-Jtr);
      if (!delta_basis.allFinite()) {
        lambda *= 10.0;
        continue;
      }
      const Vector11d delta = options.refine_pose ? delta_basis : Vector11d(B * delta_basis);
      const AffineDepthPose candidate = ApplyStep(current, delta, shared);
      const bool shifts_ok = !(options.max_shift > 0.0) ||
                             (std::abs(candidate.shift0) <= options.max_shift * options.shift_reference0 &&
                              std::abs(candidate.shift1) <= options.max_shift * options.shift_reference1);
      if (candidate.scale > 0.0 && candidate.f0 > 0.0 && candidate.f1 > 0.0 && shifts_ok &&
          cost_of(candidate, &new_cost) && new_cost < cost) {
        current = candidate;
        improved = true;
        lambda = std::max(lambda * 0.1, 1e-10);
        break;
      }
      lambda *= 10.0;
    }
    if (!improved) break;
    const double decrease = cost - new_cost;
    cost = new_cost;
    if (decrease <= options.function_tolerance * cost) {
      ++it;
      break;
    }
  }
  *model = current;
  if (summary) {
    summary->final_cost = cost;
    summary->iterations = it;
    // Covariance of the depth parameters at the solution.
    Matrix11d JtJ = Matrix11d::Zero();
    ForEachResidual<true>(p, I0, I1, Is, options.sampson_weight, current, [&](double, const Row11d& row) {
      Row11d r = row;
      if (shared) {
        r(kF0) += r(kF1);
        r(kF1) = 0.0;
      }
      JtJ.noalias() += r.transpose() * r;
    }, options.reprojection_weight);
    if (!options.refine_pose) JtJ = (B.transpose() * JtJ * B).eval();
    std::vector<int> free_index;
    for (int j = 0; j < kRelposeNumParams; ++j) {
      if (free_param[j]) free_index.push_back(j);
    }
    const int nf = static_cast<int>(free_index.size());
    Eigen::MatrixXd H(nf, nf);
    for (int a = 0; a < nf; ++a)
      for (int b = 0; b < nf; ++b) H(a, b) = JtJ(free_index[a], free_index[b]);
    // Directions the residuals leave flat (|t| without depth terms) get a tiny regularisation: their variance
    // becomes huge but, having no cross-information, they leave the others' marginals alone.
    for (int a = 0; a < nf; ++a) H(a, a) += 1e-12 * std::max(1.0, H.diagonal().cwiseAbs().maxCoeff());
    const double dof = std::max(1, num_residuals - nf);
    const Eigen::MatrixXd C = H.ldlt().solve(Eigen::MatrixXd::Identity(nf, nf)) * (cost / dof);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    double* sig[5] = {&summary->sigma_shift0, &summary->sigma_shift1, &summary->sigma_scale, &summary->sigma_f0,
                      &summary->sigma_f1};
    const int which[5] = {kShift0, kShift1, kScale, kF0, kF1};
    for (int k = 0; k < 5; ++k) {
      *sig[k] = nan;
      for (int a = 0; a < nf; ++a) {
        if (free_index[a] == which[k]) *sig[k] = C(a, a) >= 0.0 ? std::sqrt(C(a, a)) : nan;
      }
    }
  }
  return true;
}

}  // namespace madsfm
