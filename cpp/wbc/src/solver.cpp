// Control tick orchestration (dynamics terms, loop elimination, QP, efforts) and the fallback
// (Eigen only).
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
  if (!(p.friction_compensation_velocity > 0.0) || !std::isfinite(p.friction_compensation_velocity))
    throw std::invalid_argument("params.friction_compensation_velocity must be finite and > 0");
  if (!(p.spring_damping_gain >= 0.0) || !std::isfinite(p.spring_damping_gain))
    throw std::invalid_argument("params.spring_damping_gain must be finite and >= 0");
  if (!(p.qp_eps_abs > 0.0)) throw std::invalid_argument("params.qp_eps_abs must be > 0");
  if (p.qp_max_iter < 1) throw std::invalid_argument("params.qp_max_iter must be >= 1");
  if (p.qp_solver != QpSolverKind::kProxsuite && p.qp_solver != QpSolverKind::kDaqp)
    throw std::invalid_argument("params.qp_solver must be proxsuite or daqp");
  if (!(p.fallback_damping >= 0.0)) throw std::invalid_argument("params.fallback_damping must be >= 0");
}

/// x.allFinite() in one vectorised pass (x - x is 0 for a finite entry, NaN otherwise).
template <typename T>
bool allFiniteFast(const Eigen::MatrixBase<T>& x) {
  return !std::isnan((x.array() - x.array()).sum());
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

std::unique_ptr<QpSolver> makeQpSolver(QpSolverKind kind) {
  if (kind == QpSolverKind::kDaqp) return std::make_unique<DaqpQpSolver>();
  return std::make_unique<DenseQpSolver>();
}

WbcSolver::WbcSolver(const WbcModel& model, const WbcParams& params)
    : model_(model), params_(params), dynamics_(model_) {
  checkParams(params_);
  for (auto& s : solvers_) s = makeQpSolver(params_.qp_solver);
  q_work_ = model_.neutral();
  u_last_ = Vec::Zero(model_.nu());
}

void WbcSolver::reset() {
  sync();
  prep_valid_ = false;
  for (auto& s : solvers_) s->reset();
  u_last_.setZero();
  failures_ = 0;
  last_mode_ = -1;
}

const DynamicsTerms& WbcSolver::evaluate(const Eigen::Ref<const Vec>& q,
                                         const Eigen::Ref<const Vec>& v) {
  sync();
  prep_valid_ = false;  // terms_ is overwritten
  if (q.size() != model_.nq() || v.size() != model_.nv())
    throw std::invalid_argument("evaluate: q and v must have nq = " + std::to_string(model_.nq()) +
                                " and nv = " + std::to_string(model_.nv()) + " entries");
  q_work_ = q;
  const int iq = model_.baseQuaternionIdx();
  const double qn = q_work_.segment<4>(iq).norm();
  if (!(qn > 0.0) || !q_work_.allFinite() || !v.allFinite())
    throw std::invalid_argument("evaluate: q and v must be finite with a non-zero base quaternion");
  q_work_.segment<4>(iq) /= qn;
  dynamics_.compute(q_work_, v, terms_);
  return terms_;
}

void WbcSolver::prepare(const Eigen::Ref<const Vec>& q, const Eigen::Ref<const Vec>& v, bool async) {
  sync();
  prep_valid_ = false;
  if (q.size() != model_.nq() || v.size() != model_.nv()) return;  // solve() reports it
  prep_q_ = q;
  prep_v_ = v;
  if (!async) {
    runPrepared();
    return;
  }
  if (!worker_) worker_ = std::make_unique<Worker>([this] { runPrepared(); });
  worker_->start();
}

void WbcSolver::runPrepared() noexcept {
  const auto t0 = std::chrono::steady_clock::now();
  try {
    if (!prep_q_.allFinite() || !prep_v_.allFinite()) return;  // solve() reports it
    prep_loops_ok_ = computeTerms(prep_q_, prep_v_);
    prep_valid_ = true;
  } catch (...) {
    prep_valid_ = false;  // solve() computes the stage itself and reports the error
  }
  prep_time_us_ = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
}

bool WbcSolver::computeTerms(const Eigen::Ref<const Vec>& q, const Eigen::Ref<const Vec>& v) {
  q_work_ = q;
  const int iq = model_.baseQuaternionIdx();
  const double qn = q_work_.segment<4>(iq).norm();
  if (!(qn > 1e-9))
    throw std::invalid_argument("q: a non-zero base quaternion q[" + std::to_string(iq) + ":" +
                                std::to_string(iq + 4) + "]");
  q_work_.segment<4>(iq) /= qn;

  dynamics_.compute(q_work_, v, terms_);
  applySpringDamping(v);
  if (model_.hasFrictionloss())  // dry joint friction: smooth Coulomb force in h
    terms_.h.array() +=
        model_.frictionloss().array() * (v.array() / params_.friction_compensation_velocity).tanh();
  // Closed loops, kEliminate: the QP runs in the independent accelerations.
  if (model_.eliminatesLoops()) return reduceLoops(model_, terms_, reduction_, reduced_);
  return true;
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

  // The first stage: done by prepare() for this very state, or now.
  const auto tw = Clock::now();
  sync();
  // The tick's work: prepare()'s time instead of the time spent waiting for it.
  double stage_us = -std::chrono::duration<double, std::micro>(Clock::now() - tw).count();
  const int nv = model_.nv();
  bool loops_ok;
  if (prep_valid_ && prep_q_ == q && prep_v_ == v) {
    loops_ok = prep_loops_ok_;
    stage_us += prep_time_us_;
  } else {
    prep_valid_ = false;
    loops_ok = computeTerms(q, v);
  }
  const bool eliminate = model_.eliminatesLoops();
  const DynamicsTerms& qp_terms = eliminate ? reduced_ : terms_;
  bool ok = loops_ok;
  if (loops_ok) {
    buildQp(model_, params_, qp_terms, ref, q_work_, v, qp_, out.errors);
    // Finite input can still give non-finite QP data (e.g. overflow at absurd velocities).
    ok = allFiniteFast(qp_.H) && allFiniteFast(qp_.g) && allFiniteFast(qp_.A) && allFiniteFast(qp_.b) &&
         allFiniteFast(qp_.C) && !qp_.l.hasNaN() && !qp_.u.hasNaN();
  }

  const auto t1 = Clock::now();
  if (ok) {
    const int mode = qp_.layout.mode();
    QpSettings settings{params_.qp_eps_abs, params_.qp_max_iter};
    solvers_[static_cast<std::size_t>(mode)]->solve(qp_, settings, mode != last_mode_, sol_);
    last_mode_ = mode;
    out.status = sol_.status;
    out.iterations = sol_.iterations;
  } else {
    out.status = loops_ok ? QpStatus::kNonFinite : QpStatus::kSingularLoops;
    out.iterations = 0;
  }
  const auto t2 = Clock::now();

  out.wrenches.setZero(6, kNumFeet);
  const Eigen::Index n_loop = model_.nLoopRows();
  const Eigen::Index n_con = model_.nConstraintRows();
  if (out.status == QpStatus::kSolved) {
    const QpLayout& L = qp_.layout;
    recoverEfforts(model_, qp_terms, L, sol_.x, out.tau);
    if (out.tau.allFinite()) {
      if (eliminate) {
        expandAccelerations(model_, reduction_, sol_.x.head(L.nv), out.qdd);
      } else {
        out.qdd = sol_.x.head(nv);
      }
      for (int f = 0; f < kNumFeet; ++f) {
        const auto fi = static_cast<std::size_t>(f);
        if (L.contact[fi]) out.wrenches.col(f) = sol_.x.segment<6>(L.wrench_offset[fi]);
      }
      if (n_con > 0 && eliminate) {
        // lambda from the dependent rows of M qdd + h - J_c^T w - B u = J_loop^T lambda
        loop_residual_ = terms_.h;
        loop_residual_.noalias() += terms_.M * out.qdd;
        loop_residual_.noalias() -= model_.actuation() * out.tau;
        for (int f = 0; f < kNumFeet; ++f)
          if (L.contact[static_cast<std::size_t>(f)])
            loop_residual_.noalias() -= terms_.J_sole[static_cast<std::size_t>(f)].transpose() * out.wrenches.col(f);
        loopForcesFromResidual(model_, reduction_, loop_residual_, lambda_);
      } else if (n_con > 0) {
        lambda_ = sol_.x.segment(L.extra_offset, L.n_extra);
      } else {
        lambda_.resize(0);
      }
      out.loop_forces = lambda_.head(n_loop);
      springTorques(q_work_, lambda_.tail(n_con - n_loop), out.spring_torques);
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
    out.loop_forces = Vec::Zero(n_loop);
    springTorques(q_work_, Vec::Zero(n_con - n_loop), out.spring_torques);
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
  out.tick_time_us = stage_us + std::chrono::duration<double, std::micro>(t3 - t0).count();
}

void WbcSolver::applySpringDamping(const Eigen::Ref<const Vec>& v) {
  const double kd = params_.spring_damping_gain;
  const auto& rigid = model_.rigidSprings();
  if (kd == 0.0 || rigid.empty()) return;
  const Eigen::Index nl = model_.nLoopRows();
  const bool extra = terms_.J_extra.rows() == terms_.J_loop.rows();
  for (std::size_t k = 0; k < rigid.size(); ++k) {
    const Eigen::Index r = nl + static_cast<Eigen::Index>(k);
    const double g = kd * v[model_.springIdxV()[static_cast<std::size_t>(rigid[k])]];
    terms_.gamma_loop[r] = g;  // J qdd + gamma = 0  ->  qdd_s = -kd qdot_s
    if (extra) terms_.gamma_extra[r] = g;
  }
}

void WbcSolver::springTorques(const Eigen::Ref<const Vec>& q, const Eigen::Ref<const Vec>& rigid_lambda,
                              Vec& torques) const {
  const auto& sq = model_.springIdxQ();
  const WbcModelSpec& spec = model_.spec();
  torques.resize(static_cast<Eigen::Index>(sq.size()));
  for (std::size_t i = 0; i < sq.size(); ++i) {
    const auto ii = static_cast<Eigen::Index>(i);
    torques[ii] = -spec.spring_stiffness[ii] * (q[sq[i]] - spec.spring_reference[ii]);
  }
  const auto& rigid = model_.rigidSprings();
  for (std::size_t k = 0; k < rigid.size(); ++k) torques[rigid[k]] += rigid_lambda[static_cast<Eigen::Index>(k)];
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
    case QpStatus::kSingularLoops: return "singular_loops";
  }
  return "unknown";
}

}  // namespace lipmpcc::wbc
