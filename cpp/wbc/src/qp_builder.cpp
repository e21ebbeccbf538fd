// QP assembly (Eigen only): tasks -> (H, g), dynamics and no-slip -> (A, b),
// contact wrench cone and motor bounds -> (C, l, u). See qp.hpp for the formulation.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "lipmpcc/wbc/qp.hpp"

namespace lipmpcc::wbc {

namespace {

/// Adds 0.5 |J x + drift - target|^2_diag(w) to the q-block of (H, g).
template <typename JType>
void addTask(const Eigen::MatrixBase<JType>& J, const Vec3& drift, const Vec3& target,
             const Vec3& w, Eigen::Ref<Mat> Hq, Eigen::Ref<Vec> gq) {
  const Mat3x WJ = w.asDiagonal() * J;
  Hq.noalias() += J.transpose() * WJ;
  gq.noalias() += WJ.transpose() * (drift - target);
}

Vec3 pd(const TaskGains& gains, const Vec3& acc_ref, const Vec3& pos_err, const Vec3& vel_err) {
  return acc_ref + gains.kp.cwiseProduct(pos_err) + gains.kd.cwiseProduct(vel_err);
}

}  // namespace

Vec3 rotationError(const Mat3& R_ref, const Mat3& R) {
  const Eigen::AngleAxisd aa(R_ref * R.transpose());
  return aa.angle() * aa.axis();
}

QpLayout makeLayout(const WbcModel& model, const std::array<bool, kNumFeet>& contact, int n_extra,
                    int n_limits, bool torsion_cone) {
  QpLayout L;
  const QpCoordinates& qc = model.qpCoordinates();
  L.nv = qc.n;
  L.nu = model.nu();
  L.contact = contact;
  int offset = L.nv;
  for (int f = 0; f < kNumFeet; ++f) {
    const auto fi = static_cast<std::size_t>(f);
    if (contact[fi]) {
      L.wrench_offset[fi] = offset;
      offset += 6;
      ++L.n_contacts;
    } else {
      L.wrench_offset[fi] = -1;
    }
  }
  L.n_extra = n_extra;
  L.extra_offset = offset;
  L.n_var = offset + n_extra;
  L.n_unact = static_cast<int>(qc.N_T.rows());
  L.n_eq = L.n_unact + 6 * L.n_contacts + n_extra;
  L.n_limits = n_limits;
  L.n_in = (kRowsPerContactInequality + (torsion_cone ? kTorsionConeRows : 0)) * L.n_contacts + L.nu + n_limits;
  return L;
}

void buildQp(const WbcModel& model, const WbcParams& p, const DynamicsTerms& t,
             const WbcReference& ref, const Eigen::Ref<const Vec>& q, const Eigen::Ref<const Vec>& v,
             QpProblem& qp, TaskErrors& err) {
  const int n_limits = p.joint_limit_horizon > 0.0 ? model.nLimits() : 0;
  const QpLayout L = makeLayout(model, ref.contact, static_cast<int>(t.J_extra.rows()), n_limits, p.torsion_cone);
  qp.layout = L;
  const Eigen::Index nv = L.nv;
  qp.H.setZero(L.n_var, L.n_var);
  qp.g.setZero(L.n_var);
  qp.A.setZero(L.n_eq, L.n_var);
  qp.b.setZero(L.n_eq);
  qp.C.setZero(L.n_in, L.n_var);
  qp.l.setZero(L.n_in);
  qp.u.setZero(L.n_in);
  auto Hq = qp.H.topLeftCorner(nv, nv);
  auto gq = qp.g.head(nv);

  // --- tasks -------------------------------------------------------------------------------
  err.com_pos = ref.com_pos - t.com;
  err.com_vel = ref.com_vel - t.vcom;
  addTask(t.J_com, t.drift_com, pd(p.com, ref.com_acc, err.com_pos, err.com_vel), p.com.weight, Hq, gq);

  err.torso_rot = rotationError(ref.torso_rot, t.R_torso);
  err.torso_angvel = ref.torso_angvel - t.w_torso;
  addTask(t.J_torso, t.drift_torso, pd(p.torso, ref.torso_angacc, err.torso_rot, err.torso_angvel),
          p.torso.weight, Hq, gq);

  for (int f = 0; f < kNumFeet; ++f) {
    const auto fi = static_cast<std::size_t>(f);
    if (ref.contact[fi]) {
      err.foot_pos[fi].setZero();
      err.foot_rot[fi].setZero();
      continue;
    }
    const Mat6x& J = t.J_sole[fi];
    err.foot_pos[fi] = ref.foot_pos[fi] - t.p_sole[fi];
    const Vec3 ev = ref.foot_vel[fi] - t.vel_sole[fi].head<3>();
    addTask(J.topRows<3>(), Vec3(t.drift_sole[fi].head<3>()),
            pd(p.swing_position, ref.foot_acc[fi], err.foot_pos[fi], ev), p.swing_position.weight, Hq, gq);
    err.foot_rot[fi] = rotationError(ref.foot_rot[fi], t.R_sole[fi]);
    const Vec3 ew = ref.foot_angvel[fi] - t.vel_sole[fi].tail<3>();
    addTask(J.bottomRows<3>(), Vec3(t.drift_sole[fi].tail<3>()),
            pd(p.swing_orientation, ref.foot_angacc[fi], err.foot_rot[fi], ew),
            p.swing_orientation.weight, Hq, gq);
  }

  const QpCoordinates& qc = model.qpCoordinates();
  const auto& aq = model.armIdxQ();
  const auto& av = model.armIdxV();
  const auto& ax = qc.arm_idx;  // the arm joints among the QP's accelerations
  err.arm_posture.resize(static_cast<Eigen::Index>(aq.size()));
  for (std::size_t i = 0; i < aq.size(); ++i) {
    const auto ii = static_cast<Eigen::Index>(i);
    err.arm_posture[ii] = ref.arm_posture[ii] - q[aq[i]];
    const double target = p.arm_posture.kp * err.arm_posture[ii] - p.arm_posture.kd * v[av[i]];
    qp.H(ax[i], ax[i]) += p.arm_posture.weight;
    qp.g[ax[i]] -= p.arm_posture.weight * target;
  }

  err.angular_momentum = t.k_com;
  if (p.angular_momentum_weight > 0.0) {
    const Vec3 target = -p.angular_momentum_kd * t.k_com;
    addTask(t.A_ang, t.drift_k, target, Vec3::Constant(p.angular_momentum_weight), Hq, gq);
  }

  if (t.qdd_metric.size() == 0) {
    Hq.diagonal().array() += p.qdd_regularization;
  } else {  // eliminated loops: reg |qdd|^2 in the independent accelerations
    Hq += p.qdd_regularization * t.qdd_metric;
    gq += p.qdd_regularization * t.qdd_metric_g;
  }
  // Wrenches only: the multipliers of the holonomic rows are fixed by the motion (not regularised),
  // so that the multiplier and the elimination formulations share their optimum.
  for (Eigen::Index i = nv; i < L.extra_offset; ++i) qp.H(i, i) += p.force_regularization;

  // --- equalities --------------------------------------------------------------------------
  // N^T and B^+ products by rows over their non-zeros (SparseRows): mostly row selections.
  const SparseRows& NT = qc.N_T_rows;
  const Eigen::Index nun = L.n_unact;
  NT.product(t.M, 1.0, qp.A.topLeftCorner(nun, nv));
  NT.product(t.h, -1.0, qp.b.head(nun));
  Eigen::Index row = nun;
  for (int f = 0; f < kNumFeet; ++f) {
    const auto fi = static_cast<std::size_t>(f);
    if (!ref.contact[fi]) continue;
    const Eigen::Index o = L.wrench_offset[fi];
    NT.product(t.J_sole[fi].transpose(), -1.0, qp.A.block(0, o, nun, 6));
    qp.A.block(row, 0, 6, nv) = t.J_sole[fi];
    qp.b.segment<6>(row) = -t.drift_sole[fi] - p.contact_velocity_gain * t.vel_sole[fi];
    row += 6;
  }
  if (L.n_extra > 0) {
    NT.product(t.J_extra.transpose(), -1.0, qp.A.block(0, L.extra_offset, nun, L.n_extra));
    qp.A.block(row, 0, L.n_extra, nv) = t.J_extra;
    qp.b.segment(row, L.n_extra) = -t.gamma_extra;
  }

  // --- inequalities ------------------------------------------------------------------------
  const WbcModelSpec& spec = model.spec();
  const double mu = spec.friction;
  const double sL = p.cop_safety_factor * spec.foot_half_length;
  const double sW = p.cop_safety_factor * spec.foot_half_width;
  const double mu_t = mu * std::min(sL, sW);
  row = 0;
  for (int f = 0; f < kNumFeet; ++f) {
    const auto fi = static_cast<std::size_t>(f);
    if (!ref.contact[fi]) continue;
    const Eigen::Index o = L.wrench_offset[fi];
    const Mat3& R = t.R_sole[fi];
    // local component i of the force: R.col(i) . f ; of the torque: R.col(i) . tau
    const Eigen::RowVector3d nz = R.col(2).transpose();
    auto force = [&](Eigen::Index r, double sign, int axis, double coeff) {
      qp.C.block<1, 3>(r, o) = sign * R.col(axis).transpose() - coeff * nz;
    };
    auto torque = [&](Eigen::Index r, double sign, int axis, double coeff) {
      qp.C.block<1, 3>(r, o + 3) = sign * R.col(axis).transpose();
      qp.C.block<1, 3>(r, o) = -coeff * nz;
    };
    // CoP rectangle centred at c = (cx, cy) in the sole frame: moments about c are
    // (tx - cy fz, ty + cx fz, tz - cx fy + cy fx).
    const double cx = spec.sole_cop_centers[fi][0];
    const double cy = spec.sole_cop_centers[fi][1];
    force(row + 0, +1.0, 0, mu);
    force(row + 1, -1.0, 0, mu);
    force(row + 2, +1.0, 1, mu);
    force(row + 3, -1.0, 1, mu);
    torque(row + 4, +1.0, 0, sW + cy);
    torque(row + 5, -1.0, 0, sW - cy);
    torque(row + 6, +1.0, 1, sL - cx);
    torque(row + 7, -1.0, 1, sL + cx);
    torque(row + 8, +1.0, 2, mu_t);
    torque(row + 9, -1.0, 2, mu_t);
    const Eigen::RowVector3d torsion_offset = cy * R.col(0).transpose() - cx * R.col(1).transpose();
    qp.C.block<1, 3>(row + 8, o) += torsion_offset;
    qp.C.block<1, 3>(row + 9, o) -= torsion_offset;
    qp.l.segment<10>(row).setConstant(-kInfinity);
    qp.u.segment<10>(row).setZero();
    qp.C.block<1, 3>(row + 10, o) = nz;
    qp.l[row + 10] = p.min_normal_force;
    qp.u[row + 10] = std::isfinite(ref.max_normal_force[fi]) ? ref.max_normal_force[fi] : kInfinity;
    row += kRowsPerContactInequality;
    if (!p.torsion_cone) continue;
    // The yaw rows of the rectangle's contact wrench cone (Caron et al. 2015, a pyramid at each corner):
    // tz' +- (sW fx' + mu tx') +- (sL fy' + mu ty') <= mu (sL + sW) fz and
    // -tz' +- (sW fx' - mu tx') +- (sL fy' - mu ty') <= mu (sL + sW) fz; a CoP at a corner carries none.
    // A row a.f' + b.t' (moments t' about c) is, on the sole-origin wrench, (a - b x c).f + b.tau.
    const Eigen::Vector3d c3(cx, cy, 0.0);
    Eigen::Index r = row;
    for (const double sz : {1.0, -1.0}) {
      for (const double s1 : {1.0, -1.0}) {
        for (const double s2 : {1.0, -1.0}) {
          const Eigen::Vector3d b(s1 * sz * mu, s2 * sz * mu, sz);
          const Eigen::Vector3d a = Eigen::Vector3d(s1 * sW, s2 * sL, -mu * (sL + sW)) - b.cross(c3);
          qp.C.block<1, 3>(r, o) = (R * a).transpose();
          qp.C.block<1, 3>(r, o + 3) = (R * b).transpose();
          qp.l[r] = -kInfinity;
          qp.u[r] = 0.0;
          ++r;
        }
      }
    }
    row += kTorsionConeRows;
  }
  const SparseRows& Bp = qc.B_pinv_rows;
  const Eigen::Index nu = L.nu;
  Bp.product(t.M, 1.0, qp.C.block(row, 0, nu, nv));
  for (int f = 0; f < kNumFeet; ++f) {
    const auto fi = static_cast<std::size_t>(f);
    if (!ref.contact[fi]) continue;
    Bp.product(t.J_sole[fi].transpose(), -1.0, qp.C.block(row, L.wrench_offset[fi], nu, 6));
  }
  if (L.n_extra > 0)
    Bp.product(t.J_extra.transpose(), -1.0, qp.C.block(row, L.extra_offset, nu, L.n_extra));
  auto Bh = qp.u.segment(row, nu);  // B^+ h, then the bounds in place
  Bp.product(t.h, 1.0, Bh);
  qp.l.segment(row, nu) = (model.uMin() - Bh).cwiseMax(-kInfinity);
  qp.u.segment(row, nu) = (model.uMax() - Bh).cwiseMin(kInfinity);
  row += nu;

  // Joint position limits over the horizon h: lo <= q + v h + qdd h^2 / 2 <= hi.
  if (L.n_limits > 0) {
    const double h = p.joint_limit_horizon;
    const double s = 2.0 / (h * h);
    const auto& lq = model.limitIdxQ();
    const auto& lv = model.limitIdxV();
    const auto& lx = qc.limit_idx;
    for (int k = 0; k < L.n_limits; ++k) {
      const auto kk = static_cast<std::size_t>(k);
      const double predicted = q[lq[kk]] + v[lv[kk]] * h;
      qp.C(row + k, lx[kk]) = 1.0;
      qp.l[row + k] = s * (model.limitLower()[k] - predicted);
      qp.u[row + k] = s * (model.limitUpper()[k] - predicted);
    }
  }
}

void recoverEfforts(const WbcModel& model, const DynamicsTerms& t, const QpLayout& L,
                    const Eigen::Ref<const Vec>& x, Vec& u) {
  Vec gen = t.h;
  gen.noalias() += t.M * x.head(L.nv);
  for (int f = 0; f < kNumFeet; ++f) {
    const auto fi = static_cast<std::size_t>(f);
    if (!L.contact[fi]) continue;
    gen.noalias() -= t.J_sole[fi].transpose() * x.segment<6>(L.wrench_offset[fi]);
  }
  if (L.n_extra > 0) gen.noalias() -= t.J_extra.transpose() * x.segment(L.extra_offset, L.n_extra);
  u.resize(model.nu());
  model.qpCoordinates().B_pinv_rows.product(gen, 1.0, u);
}

}  // namespace lipmpcc::wbc
