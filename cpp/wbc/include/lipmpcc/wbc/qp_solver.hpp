// A persistent proxsuite dense QP, warm-started from its previous result across ticks.
// proxsuite is hidden behind a pointer so that only qp_solver.cpp compiles its headers.
#pragma once

#include <memory>

#include "lipmpcc/wbc/qp.hpp"

namespace lipmpcc::wbc {

struct QpSettings {
  double eps_abs = 1e-6;
  int max_iter = 50;  ///< outer and inner iteration limit
};

struct QpSolution {
  QpStatus status = QpStatus::kNotRun;
  int iterations = 0;
  bool cold_restart = false;  ///< the warm-started solve failed and a cold solve was tried.
  Vec x;
};

class DenseQpSolver {
 public:
  DenseQpSolver();
  ~DenseQpSolver();
  DenseQpSolver(const DenseQpSolver&) = delete;
  DenseQpSolver& operator=(const DenseQpSolver&) = delete;

  /// Solves `qp`. The first call (or a call after reset() / a size change / a failure) builds and
  /// equilibrates a fresh proxsuite object; later calls update its matrices and warm-start from
  /// the previous result. A failed warm-started solve is retried once from a cold start.
  /// Never throws: solver exceptions become QpStatus::kException.
  void solve(const QpProblem& qp, const QpSettings& settings, bool refresh_preconditioner,
             QpSolution& out);
  void reset();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lipmpcc::wbc
