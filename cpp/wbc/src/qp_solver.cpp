// proxsuite translation unit. Warm start goes through the persistent object
// (WARM_START_WITH_PREVIOUS_RESULT + update + solve()): solve(x, y, z) is not used (see TOOLCHAIN:
// it mishandles z when box constraints are on).
#include <proxsuite/proxqp/dense/dense.hpp>

#include <optional>

#include "lipmpcc/wbc/qp_solver.hpp"

namespace lipmpcc::wbc {

namespace pq = proxsuite::proxqp;

struct DenseQpSolver::Impl {
  std::optional<pq::dense::QP<double>> qp;
  Eigen::Index n = -1, n_eq = -1, n_in = -1;
  bool needs_init = true;
};

DenseQpSolver::DenseQpSolver() : impl_(std::make_unique<Impl>()) {}
DenseQpSolver::~DenseQpSolver() = default;

void DenseQpSolver::reset() {
  impl_->qp.reset();
  impl_->needs_init = true;
}

namespace {

QpStatus convert(pq::QPSolverOutput s) {
  switch (s) {
    case pq::QPSolverOutput::PROXQP_SOLVED: return QpStatus::kSolved;
    case pq::QPSolverOutput::PROXQP_MAX_ITER_REACHED: return QpStatus::kMaxIterReached;
    case pq::QPSolverOutput::PROXQP_PRIMAL_INFEASIBLE: return QpStatus::kPrimalInfeasible;
    case pq::QPSolverOutput::PROXQP_SOLVED_CLOSEST_PRIMAL_FEASIBLE:
      return QpStatus::kSolvedClosestPrimalFeasible;
    case pq::QPSolverOutput::PROXQP_DUAL_INFEASIBLE: return QpStatus::kDualInfeasible;
    case pq::QPSolverOutput::PROXQP_NOT_RUN: return QpStatus::kNotRun;
  }
  return QpStatus::kNotRun;
}

void configure(pq::dense::QP<double>& qp, const QpSettings& s) {
  qp.settings.eps_abs = s.eps_abs;
  qp.settings.eps_rel = 0.0;
  // Bound the work of a failing solve (outer x inner iterations): a control tick must end.
  qp.settings.max_iter = s.max_iter;
  qp.settings.max_iter_in = s.max_iter;
  // Infeasibility certificates at proxsuite's default threshold (1e-4) fire falsely on the badly
  // scaled QPs of closed-loop models (rod inertias ~1e-6 next to a 48 kg base); a truly
  // infeasible QP still ends at max_iter and goes to the fallback.
  qp.settings.eps_primal_inf = 1e-12;
  qp.settings.eps_dual_inf = 1e-12;
  qp.settings.verbose = false;
  qp.settings.compute_timings = false;
  qp.settings.initial_guess = pq::InitialGuessStatus::WARM_START_WITH_PREVIOUS_RESULT;
}

}  // namespace

void DenseQpSolver::solve(const QpProblem& p, const QpSettings& settings, bool refresh_preconditioner,
                          QpSolution& out) {
  Impl& s = *impl_;
  const QpLayout& L = p.layout;
  out.cold_restart = false;
  auto cold_solve = [&]() {
    s.qp.emplace(L.n_var, L.n_eq, L.n_in);
    configure(*s.qp, settings);
    // First solve of a fresh object: no previous result, start from the equality-constrained guess.
    s.qp->settings.initial_guess = pq::InitialGuessStatus::EQUALITY_CONSTRAINED_INITIAL_GUESS;
    s.qp->init(p.H, p.g, p.A, p.b, p.C, p.l, p.u, true);
    s.qp->solve();
    s.qp->settings.initial_guess = pq::InitialGuessStatus::WARM_START_WITH_PREVIOUS_RESULT;
    s.n = L.n_var;
    s.n_eq = L.n_eq;
    s.n_in = L.n_in;
  };
  try {
    const bool same_size = s.qp && s.n == L.n_var && s.n_eq == L.n_eq && s.n_in == L.n_in;
    if (s.needs_init || !same_size) {
      cold_solve();
    } else {
      s.qp->update(p.H, p.g, p.A, p.b, p.C, p.l, p.u, refresh_preconditioner);
      s.qp->solve();
      if (s.qp->results.info.status != pq::QPSolverOutput::PROXQP_SOLVED) {
        out.cold_restart = true;
        cold_solve();
      }
    }
    out.status = convert(s.qp->results.info.status);
    out.iterations = static_cast<int>(s.qp->results.info.iter);
    out.x = s.qp->results.x;
    if (out.status == QpStatus::kSolved && !out.x.allFinite()) out.status = QpStatus::kNonFinite;
  } catch (const std::exception&) {
    out.status = QpStatus::kException;
    out.iterations = 0;
  }
  // After a failure the stored iterate is not a useful warm start: rebuild next tick.
  s.needs_init = out.status != QpStatus::kSolved;
}

}  // namespace lipmpcc::wbc
