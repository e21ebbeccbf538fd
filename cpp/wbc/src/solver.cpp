// Control tick orchestration and the fallback (Eigen only).
#include <Eigen/LU>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "lipmpcc/wbc/solver.hpp"

namespace lipmpcc::wbc {

namespace {

void checkGains(const TaskGains& g, const char* name) {
  if (!(g.weight.array() >= 0.0).all() || !(g.kp.array() >= 0.0).all() || !(g.kd.array() >= 0.0).all() ||
      !g.weight.allFinite() || !g.kp.allFinite() || !g.kd.allFinite())
    throw std::invalid_argument(std::string("params.") + name +
                                ": weights and gains must be finite and >= 0");
}

void checkParams(const WbcParams& p) {
  checkGains(p.com, "com");
  checkGains(p.torso, "torso");
  checkGains(p.swing_position, "swing_position");
  checkGains(p.swing_orientation, "swing_orientation");
  const auto& a = p.arm_posture;
  if (!(a.weight >= 0.0 && a.kp >= 0.0 && a.kd >= 0.0) || !std::isfinite(a.weight + a.kp + a.kd))
    throw std::invalid_argument("params.arm_posture: weight and gains must be finite and >= 0");
  if (!(p.angular_momentum_weight >= 0.0) || !(p.angular_momentum_kd >= 0.0))
    throw std::invalid_argument("params.angular_momentum_*: must be >= 0");
  if (!(p.qdd_regularization > 0.0) || !(p.force_regularization > 0.0))
    throw std::invalid_argument("params: qdd_regularization and force_regularization must be > 0 "
                                "(they make the QP strictly convex)");
  if (!(p.min_normal_force >= 0.0)) throw std::invalid_argument("params.min_normal_force must be >= 0");
  if (!(p.cop_safety_factor > 0.0 && p.cop_safety_factor <= 1.0))
    throw std::invalid_argument("params.cop_safety_factor must be in (0, 1]");
  if (!(p.contact_velocity_gain >= 0.0))
    throw std::invalid_argument("params.contact_velocity_gain must be >= 0");
  if (!(p.qp_eps_abs > 0.0)) throw std::invalid_argument("params.qp_eps_abs must be > 0");
  if (p.qp_max_iter < 1) throw std::invalid_argument("params.qp_max_iter must be >= 1");
  if (!(p.fallback_damping >= 0.0)) throw std::invalid_argument("params.fallback_damping must be >= 0");
}

void checkFinite(const Eigen::Ref<const Mat>& x, const char* name) {
  if (!x.allFinite()) throw std::invalid_argument(std::string(name) + ": finite values (no NaN or inf)");
}

void checkRotation(const Mat3& R, const char* name) {
  checkFinite(R, name);
  const double err = (R.transpose() * R - Mat3::Identity()).cwiseAbs().maxCoeff();
  if (err > 1e-6 || R.determinant() <= 0.0)
    throw std::invalid_argument(std::string(name) +
                                ": a rotation matrix (orthonormal to 1e-6, determinant +1)");
}

void checkReference(const WbcReference& r, int n_arm, double min_normal_force) {
  checkFinite(r.com_pos, "ref.com_pos");
  checkFinite(r.com_vel, "ref.com_vel");
  checkFinite(r.com_acc, "ref.com_acc");
  checkRotation(r.torso_rot, "ref.torso_rot");
  checkFinite(r.torso_angvel, "ref.torso_angvel");
  checkFinite(r.torso_angacc, "ref.torso_angacc");
  for (std::size_t f = 0; f < kNumFeet; ++f) {
    if (r.contact[f]) {
      if (std::isnan(r.max_normal_force[f]) || !(r.max_normal_force[f] >= min_normal_force))
        throw std::invalid_argument("ref.max_normal_force: bounds >= params.min_normal_force (" +
                                    std::to_string(min_normal_force) + " N) for a foot in contact");
      continue;  // swing fields of a stance foot are ignored
    }
    checkFinite(r.foot_pos[f], "ref.foot_pos");
    checkFinite(r.foot_vel[f], "ref.foot_vel");
    checkFinite(r.foot_acc[f], "ref.foot_acc");
    checkRotation(r.foot_rot[f], "ref.foot_rot");
    checkFinite(r.foot_angvel[f], "ref.foot_angvel");
    checkFinite(r.foot_angacc[f], "ref.foot_angacc");
  }
  if (r.arm_posture.size() != n_arm)
    throw std::invalid_argument("ref.arm_posture: " + std::to_string(n_arm) + " entries (got " +
                                std::to_string(r.arm_posture.size()) + ")");
  checkFinite(r.arm_posture, "ref.arm_posture");
}

}  // namespace

WbcSolver::WbcSolver(const WbcModel& model, const WbcParams& params)
    : model_(model), params_(params), dynamics_(model_) {
  checkParams(params_);
  q_work_ = model_.neutral();
  u_last_ = Vec::Zero(model_.nu());
}

void WbcSolver::reset() {
  for (auto& s : solvers_) s.reset();
  u_last_.setZero();
  failures_ = 0;
  last_mode_ = -1;
}

const DynamicsTerms& WbcSolver::evaluate(const Eigen::Ref<const Vec>& q,
                                         const Eigen::Ref<const Vec>& v) {
  if (q.size() != model_.nq() || v.size() != model_.nv())
    throw std::invalid_argument("evaluate: q and v must have nq = " + std::to_string(model_.nq()) +
                                " and nv = " + std::to_string(model_.nv()) + " entries");
  q_work_ = q;
  const double qn = q_work_.segment<4>(3).norm();
  if (!(qn > 0.0) || !q_work_.allFinite() || !v.allFinite())
    throw std::invalid_argument("evaluate: q and v must be finite with a non-zero base quaternion");
  q_work_.segment<4>(3) /= qn;
  dynamics_.compute(q_work_, v, terms_);
  return terms_;
}

WbcOutput WbcSolver::solve(const Eigen::Ref<const Vec>& q, const Eigen::Ref<const Vec>& v,
                           const WbcReference& ref) {
  WbcOutput out;
  solveInto(q, v, ref, out);
  return out;
}

void WbcSolver::solveInto(const Eigen::Ref<const Vec>& q, const Eigen::Ref<const Vec>& v,
                          const WbcReference& ref, WbcOutput& out) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  if (q.size() != model_.nq())
    throw std::invalid_argument("q: " + std::to_string(model_.nq()) + " entries (got " +
                                std::to_string(q.size()) + ")");
  if (v.size() != model_.nv())
    throw std::invalid_argument("v: " + std::to_string(model_.nv()) + " entries (got " +
                                std::to_string(v.size()) + ")");
  checkFinite(q, "q");
  checkFinite(v, "v");
  checkReference(ref, model_.nArm(), params_.min_normal_force);

  q_work_ = q;
  const double qn = q_work_.segment<4>(3).norm();
  if (!(qn > 1e-9)) throw std::invalid_argument("q: a non-zero base quaternion q[3:7]");
  q_work_.segment<4>(3) /= qn;

  const int nv = model_.nv();
  dynamics_.compute(q_work_, v, terms_);
  buildQp(model_, params_, terms_, ref, q_work_, v, qp_, out.errors);
  // Finite input can still give non-finite QP data (e.g. overflow at absurd velocities).
  const bool ok = qp_.H.allFinite() && qp_.g.allFinite() && qp_.A.allFinite() && qp_.b.allFinite() &&
                  qp_.C.allFinite() && !qp_.l.hasNaN() && !qp_.u.hasNaN();

  const auto t1 = Clock::now();
  if (ok) {
    const int mode = qp_.layout.mode();
    QpSettings settings{params_.qp_eps_abs, params_.qp_max_iter};
    solvers_[static_cast<std::size_t>(mode)].solve(qp_, settings, mode != last_mode_, sol_);
    last_mode_ = mode;
    out.status = sol_.status;
    out.iterations = sol_.iterations;
  } else {
    out.status = QpStatus::kNonFinite;
    out.iterations = 0;
  }
  const auto t2 = Clock::now();

  out.wrenches.setZero(6, kNumFeet);
  if (out.status == QpStatus::kSolved) {
    recoverEfforts(model_, terms_, qp_.layout, sol_.x, out.tau);
    if (out.tau.allFinite()) {
      out.qdd = sol_.x.head(nv);
      for (int f = 0; f < kNumFeet; ++f) {
        const auto fi = static_cast<std::size_t>(f);
        if (qp_.layout.contact[fi]) out.wrenches.col(f) = sol_.x.segment<6>(qp_.layout.wrench_offset[fi]);
      }
      out.used_fallback = false;
      u_last_ = out.tau;
    } else {
      out.status = QpStatus::kNonFinite;
    }
  }
  if (out.status != QpStatus::kSolved) {
    ++failures_;
    out.used_fallback = true;
    out.qdd = Vec::Zero(nv);
    out.wrenches.setZero();
    out.tau = u_last_;
    out.tau.noalias() -= params_.fallback_damping * (model_.actuation().transpose() * v);
    out.tau = out.tau.cwiseMax(model_.uMin()).cwiseMin(model_.uMax());
    // u_last_ keeps the last QP solution: repeated failures do not integrate the damping term.
    if (!ok) out.errors = TaskErrors{};
  }
  out.tau_joint.noalias() = model_.actuation() * out.tau;
  const auto t3 = Clock::now();
  out.solve_time_us = std::chrono::duration<double, std::micro>(t2 - t1).count();
  out.tick_time_us = std::chrono::duration<double, std::micro>(t3 - t0).count();
}

const char* statusName(QpStatus s) {
  switch (s) {
    case QpStatus::kSolved: return "solved";
    case QpStatus::kMaxIterReached: return "max_iter_reached";
    case QpStatus::kPrimalInfeasible: return "primal_infeasible";
    case QpStatus::kDualInfeasible: return "dual_infeasible";
    case QpStatus::kSolvedClosestPrimalFeasible: return "solved_closest_primal_feasible";
    case QpStatus::kNotRun: return "not_run";
    case QpStatus::kNonFinite: return "non_finite";
    case QpStatus::kException: return "exception";
  }
  return "unknown";
}

}  // namespace lipmpcc::wbc
