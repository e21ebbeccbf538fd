// The dense QP solvers of the whole-body QP behind one interface (QpSolver), each persistent and
// warm-started across ticks: proxsuite (DenseQpSolver, qp_solver.cpp) and DAQP (DaqpQpSolver,
// qp_solver_daqp.cpp, the vendored C sources in cpp/third_party/daqp). Each solver's headers are
// hidden behind a pointer so that only its own translation unit compiles them.
#pragma once

#include <memory>

#include "lipmpcc/wbc/qp.hpp"

namespace lipmpcc::wbc {

struct QpSettings {
  double eps_abs = 1e-6;  ///< proxsuite: absolute tolerance; DAQP: primal feasibility tolerance
  int max_iter = 50;  ///< proxsuite: outer and inner iteration limit; DAQP: 20 x this active-set changes
};

struct QpSolution {
  QpStatus status = QpStatus::kNotRun;
  int iterations = 0;
  bool cold_restart = false;  ///< the warm-started solve failed and a cold solve was tried.
  Vec x;
};

/// A persistent dense QP solver: min 1/2 x'Hx + g'x s.t. Ax = b, l <= Cx <= u (QpProblem).
class QpSolver {
 public:
  virtual ~QpSolver() = default;
  /// Solves `qp`, warm-started from the previous call when the sizes agree. Never throws: solver
  /// exceptions become QpStatus::kException. `refresh_preconditioner`: the first tick after a support-mode
  /// switch (proxsuite re-equilibrates; DAQP ignores it).
  virtual void solve(const QpProblem& qp, const QpSettings& settings, bool refresh_preconditioner,
                     QpSolution& out) = 0;
  /// Forgets the warm start.
  virtual void reset() = 0;
};

/// A new solver of the given kind.
std::unique_ptr<QpSolver> makeQpSolver(QpSolverKind kind);

/// proxsuite's dense QP.
class DenseQpSolver final : public QpSolver {
 public:
  DenseQpSolver();
  ~DenseQpSolver() override;
  DenseQpSolver(const DenseQpSolver&) = delete;
  DenseQpSolver& operator=(const DenseQpSolver&) = delete;

  /// Solves `qp`. The first call (or a call after reset() / a size change / a failure) builds and
  /// equilibrates a fresh proxsuite object; later calls update its matrices and warm-start from
  /// the previous result. A failed warm-started solve is retried once from a cold start.
  /// Never throws: solver exceptions become QpStatus::kException.
  void solve(const QpProblem& qp, const QpSettings& settings, bool refresh_preconditioner,
             QpSolution& out) override;
  void reset() override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// DAQP (dual active-set; Arnstroem et al. 2022). The equalities are constraints that stay in the
/// working set (DAQP's sense ACTIVE | IMMUTABLE); each call re-factorises H (Cholesky) and forms the
/// dual problem, then starts from the previous solution's working set (the same layout only). A
/// failed warm-started solve is retried once from an empty working set; after a failure the next
/// call starts from scratch. A positive semi-definite H (the multiplier formulation of closed
/// loops) goes through DAQP's proximal-point iterations.
class DaqpQpSolver final : public QpSolver {
 public:
  DaqpQpSolver();
  ~DaqpQpSolver() override;
  DaqpQpSolver(const DaqpQpSolver&) = delete;
  DaqpQpSolver& operator=(const DaqpQpSolver&) = delete;

  void solve(const QpProblem& qp, const QpSettings& settings, bool refresh_preconditioner,
             QpSolution& out) override;
  void reset() override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lipmpcc::wbc
