// DAQP translation unit (the vendored C sources in cpp/third_party/daqp). The QP
//   min 1/2 x'Hx + g'x  s.t.  Ax = b,  l <= Cx <= u
// is handed to DAQP as the general constraints [A; C] (row-major), the equalities with bounds b <= Ax <= b
// and sense ACTIVE | IMMUTABLE (they never leave the working set). A persistent workspace keeps the
// working set of the previous solution: daqp_update_ldp without DAQP_UPDATE_sense re-forms the dual
// problem from the new data and re-activates the constraints that were active, so a tick whose active
// set did not change costs one Cholesky of H, one product M = A R^-1 and one LDL' of the active rows.
extern "C" {
#include "api.h"
#include "utils.h"
}

#include <algorithm>
#include <vector>

#include "lipmpcc/wbc/qp_solver.hpp"

namespace lipmpcc::wbc {

namespace {

using RowMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

QpStatus convert(int exitflag) {
  switch (exitflag) {
    case DAQP_EXIT_OPTIMAL:
    case DAQP_EXIT_SOFT_OPTIMAL: return QpStatus::kSolved;  // (no soft constraints here)
    case DAQP_EXIT_OPTIMAL_INEXACT: return QpStatus::kSolvedClosestPrimalFeasible;
    case DAQP_EXIT_INFEASIBLE:
    case DAQP_EXIT_OVERDETERMINED_INITIAL: return QpStatus::kPrimalInfeasible;
    case DAQP_EXIT_UNBOUNDED: return QpStatus::kDualInfeasible;
    case DAQP_EXIT_CYCLE:
    case DAQP_EXIT_ITERLIMIT:
    case DAQP_EXIT_TIMELIMIT: return QpStatus::kMaxIterReached;
    default: return QpStatus::kException;  // non-convex, unsupported, setup errors
  }
}

}  // namespace

struct DaqpQpSolver::Impl {
  DAQPWorkspace work{};  // zero-initialised: every pointer NULL until setup
  DAQPSettings settings{};
  DAQPProblem problem{};
  bool set_up = false;
  bool needs_init = true;
  Eigen::Index n = -1, n_eq = -1, n_in = -1;
  // The problem's data in DAQP's layout (DAQPProblem points into these).
  Mat H;
  Vec f;
  RowMat M;
  Vec bu, bl;
  std::vector<int> sense;
  Vec x, lam;

  ~Impl() { release(); }

  void release() {
    if (!set_up) return;
    work.settings = nullptr;  // ours, not DAQP's to free
    free_daqp_workspace(&work);
    free_daqp_ldp(&work);
    work = DAQPWorkspace{};
    set_up = false;
  }

  /// Copies the QP into DAQP's layout (allocating only when the sizes change).
  void load(const QpProblem& p) {
    const Eigen::Index ne = p.layout.n_eq, ni = p.layout.n_in, nv = p.layout.n_var;
    H = p.H;  // symmetric: row- and column-major agree
    f = p.g;
    M.resize(ne + ni, nv);
    M.topRows(ne) = p.A;
    M.bottomRows(ni) = p.C;
    bu.resize(ne + ni);
    bl.resize(ne + ni);
    bu.head(ne) = p.b;
    bl.head(ne) = p.b;
    // kInfinity (1e20, proxsuite's "no bound") becomes DAQP's own
    bu.tail(ni) = p.u.unaryExpr([](double v) { return v >= kInfinity ? DAQP_INF : v; });
    bl.tail(ni) = p.l.unaryExpr([](double v) { return v <= -kInfinity ? -DAQP_INF : v; });
  }

  void pointProblem() {
    problem.n = static_cast<int>(n);
    problem.m = static_cast<int>(n_eq + n_in);
    problem.ms = 0;
    problem.H = H.data();
    problem.f = f.data();
    problem.A = M.data();
    problem.bupper = bu.data();
    problem.blower = bl.data();
    problem.sense = sense.data();
    problem.break_points = nullptr;
    problem.nh = 0;
    problem.problem_type = 0;
  }

  void configure(const QpSettings& s) {
    daqp_default_settings(&settings);
    settings.primal_tol = s.eps_abs;
    settings.iter_limit = 20 * s.max_iter;
  }

  /// A fresh workspace: only the equalities in the working set. Returns DAQP's setup flag.
  int setup(const QpSettings& s) {
    release();
    sense.assign(static_cast<std::size_t>(n_eq + n_in), 0);
    std::fill(sense.begin(), sense.begin() + n_eq, DAQP_ACTIVE + DAQP_IMMUTABLE);
    configure(s);
    pointProblem();
    work.settings = &settings;
    const int flag = setup_daqp(&problem, &work, nullptr);
    if (flag < 0) {
      work.settings = nullptr;
      free_daqp_ldp(&work);  // setup_daqp freed the rest
      work = DAQPWorkspace{};
      return flag;
    }
    set_up = true;
    return flag;
  }

  /// Solves the loaded problem from the workspace's working set; returns DAQP's exit flag.
  int run(int& iterations) {
    x.resize(n);
    lam.resize(n_eq + n_in);
    DAQPResult res{};
    res.x = x.data();
    res.lam = lam.data();
    daqp_solve(&res, &work);
    iterations = res.iter;
    return res.exitflag;
  }
};

DaqpQpSolver::DaqpQpSolver() : impl_(std::make_unique<Impl>()) {}
DaqpQpSolver::~DaqpQpSolver() = default;

void DaqpQpSolver::reset() {
  impl_->release();
  impl_->needs_init = true;
}

void DaqpQpSolver::solve(const QpProblem& p, const QpSettings& settings, bool /*refresh_preconditioner*/,
                         QpSolution& out) {
  Impl& s = *impl_;
  const QpLayout& L = p.layout;
  out.cold_restart = false;
  int flag = 0;
  int iterations = 0;
  try {
    const bool same_size = s.set_up && s.n == L.n_var && s.n_eq == L.n_eq && s.n_in == L.n_in;
    s.n = L.n_var;
    s.n_eq = L.n_eq;
    s.n_in = L.n_in;
    s.load(p);
    auto cold = [&]() {
      flag = s.setup(settings);
      if (flag >= 0) flag = s.run(iterations);
    };
    if (s.needs_init || !same_size) {
      cold();
    } else {
      s.configure(settings);
      s.pointProblem();
      // Everything but the constraint states: the working set of the last solution is re-activated.
      flag = daqp_update_ldp(DAQP_UPDATE_Rinv + DAQP_UPDATE_M + DAQP_UPDATE_v + DAQP_UPDATE_d, &s.work,
                             &s.problem);
      if (flag >= 0) flag = s.run(iterations);
      if (flag != DAQP_EXIT_OPTIMAL) {
        out.cold_restart = true;
        int warm_iterations = iterations;
        cold();
        iterations += warm_iterations;
      }
    }
    out.status = convert(flag);
    out.iterations = iterations;
    out.x = s.x;
    if (out.status == QpStatus::kSolved && !out.x.allFinite()) out.status = QpStatus::kNonFinite;
  } catch (const std::exception&) {
    out.status = QpStatus::kException;
    out.iterations = 0;
  }
  // After a failure the working set is not a useful warm start: start from scratch next tick.
  s.needs_init = out.status != QpStatus::kSolved;
}

}  // namespace lipmpcc::wbc
