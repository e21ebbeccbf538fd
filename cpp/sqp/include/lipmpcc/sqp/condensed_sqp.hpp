// The SQP of lipmpcc.solvers.condensed_sqp.CondensedSqp in C++, step for step:
//   min f(u, θ)  s.t.  lbg ≤ g(u, θ) ≤ ubg,  lbu ≤ u ≤ ubu
// Each iteration: the exact Hessian of the Lagrangian made positive definite (by default its eigenvalues
// raised to eig_floor: PartialEigenClip, or Eigen's SelfAdjointEigenSolver; or Gill–Murray–Wright's modified Cholesky
// factorisation with its pivots at least eig_floor, the factor handed to DAQP), the QP on [Δ, ∇g Δ] solved by DAQP (vendored C, cold like daqp.solve), a
// backtracking line search on the ℓ1 merit function with an optional second-order correction, the
// optional rate stop and the multiplier update. The derivatives are CasADi-generated C functions:
//   terms(u, θ..., λ) -> (f, ∇f, g, ∇g (m × n), ∇²L (n × n)),  merit(u, θ...) -> (f, g).
#pragma once

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <memory>
#include <string>
#include <vector>

#include "lipmpcc/sqp/casadi_function.hpp"
#include "lipmpcc/sqp/eigen_clip.hpp"

namespace lipmpcc::sqp {

using Vec = Eigen::VectorXd;
using RowMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// How the Hessian of the Lagrangian is made positive definite (lipmpcc/solvers/convexify.py).
enum class Convexification {
  EigenClip = 0,         ///< eigenvalues raised to eig_floor (the reference)
  ModifiedCholesky = 1,  ///< H + E = L D Lᵀ (Gill–Murray–Wright, no pivoting), R = √D Lᵀ given to DAQP
};

/// The solver's options (CondensedSqp's arguments of the same names).
struct SqpSettings {
  int max_iter = 100;
  double tol = 1e-4;                      ///< stop when max |step| < tol
  double eig_floor = 1.0;                 ///< the Hessian's eigenvalues (or pivots) are raised to at least this
  Convexification convexification = Convexification::EigenClip;
  /// EigenClip through the tridiagonal form with only the eigenvectors below the floor (PartialEigenClip; the
  /// full eigendecomposition when it cannot vouch for its result) instead of Eigen's full eigendecomposition
  bool partial_eigen = true;
  double second_order_correction = 0.0;   ///< SOC for rejected full steps shorter than this (max-norm); 0: never
  double rate_stop = 0.0;                 ///< > 0: stop when the estimated distance left < rate_stop · tol
  /// DAQP from the working set of the previous QP (of this or the last solve; the same solutions, other
  /// rounding and QP iterations) instead of cold as daqp.solve
  bool warm_start = false;
};

/// One SQP iteration as recorded in CondensedSqp.trace.
struct TraceRow {
  int iteration;
  double alpha;
  double max_du;
  double qp_iterations;
};

/// One solve's result (SqpSolution plus the multipliers kept for the next warm start and counters).
struct SqpResult {
  bool found = false;
  std::string status;
  int iterations = 0;
  double cost = 0.0;
  Vec u;
  Vec lam;              ///< multipliers for the next solve (zeros unless found)
  double qp_time = 0.0; ///< time in DAQP during this solve [s]
  long qp_iters = 0;    ///< DAQP iterations during this solve
  std::vector<TraceRow> trace;  ///< filled when requested
};

class CondensedSqp {
 public:
  /// ``terms`` and ``merit`` as above (their parameter inputs in the same order); bounds may be ±inf.
  /// Throws std::invalid_argument when the sizes disagree.
  CondensedSqp(std::shared_ptr<CasadiFunction> terms, std::shared_ptr<CasadiFunction> merit, const Vec& lbg,
               const Vec& ubg, const Vec& lbu, const Vec& ubu, const SqpSettings& settings);
  ~CondensedSqp();

  int nu() const { return nu_; }
  int m() const { return m_; }
  int nParams() const { return n_params_; }
  int paramSize(int i) const { return terms_->inSize(1 + i); }
  const SqpSettings& settings() const { return settings_; }

  /// Evaluates the problem with ``terms`` and ``merit`` from now on (e.g. the compiled libraries of the functions
  /// that were callbacks so far: the same numbers, faster), keeping the warm start; ``nullptr`` keeps that one.
  /// Throws std::invalid_argument when a function's inputs or outputs differ from the one it replaces.
  void replaceFunctions(std::shared_ptr<CasadiFunction> terms, std::shared_ptr<CasadiFunction> merit);
  /// Whether the terms (0) or the merit (1) function is evaluated by a callback.
  bool usesCallback(int which) const { return (which == 0 ? terms_ : merit_)->isCallback(); }

  /// Solves from ``u0`` (n) with the parameter values ``params`` and the warm-start multipliers ``lam``
  /// (m); ``record_trace`` fills SqpResult::trace. Throws std::invalid_argument for a wrong size or a value
  /// that is not finite.
  SqpResult solve(const Vec& u0, const std::vector<Vec>& params, const Vec& lam, bool record_trace);

 private:
  struct Qp;
  struct Merit {
    bool valid = false;
    Vec point;
    double cost = 0.0, violation = 0.0;
  };
  struct Step {
    double alpha;
    Vec step;
    Vec lam_qp;
    Merit merit;
  };

  double violation(const Vec& g) const;
  void qpBounds(const Vec& u, const Vec& g);
  int solveQp(const Vec& grad, SqpResult& out, bool bounds_only);
  void evalMerit(const Vec& u, double& cost, Vec& g);
  Step lineSearch(const Vec& u, const Vec& du, const Vec& grad, const Vec& g, double cost, const Vec& lam_qp,
                  SqpResult& out);
  /// The second-order correction of a rejected full step: the QP with the constraint values ``g_c`` =
  /// g(u + Δ) − ∇g Δ; true (and ``step``) when its merit is at most ``phi_max``.
  bool correctedStep(const Vec& u, const Vec& grad, const Vec& g_c, double nu_merit, double phi_max, Step& step,
                     SqpResult& out);
  bool contracted(double size, double prev_size, double alpha, const Merit& merit) const;
  void convexify();
  /// The modified Cholesky factor of h_col_'s lower triangle into rpack_ (R = √D Lᵀ packed by rows, as
  /// DAQP's problem_type 2 takes it).
  void modifiedCholesky();

  std::shared_ptr<CasadiFunction> terms_, merit_;
  SqpSettings settings_;
  int nu_ = 0, m_ = 0, n_params_ = 0;
  Vec lbg_, ubg_, lbu_, ubu_, lo_g_, hi_g_;
  std::vector<int> free_lo_rows_, free_hi_rows_;
  // per-solve buffers
  std::vector<const double*> args_;
  Vec u_buf_, lam_buf_, grad_, g_, g_merit_, jg_col_, h_col_;
  double cost_ = 0.0;
  RowMat jg_, h_;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig_;
  Eigen::MatrixXd vw_;
  PartialEigenClip partial_;
  Eigen::MatrixXd h_partial_;
  Eigen::MatrixXd chol_;  ///< the modified Cholesky's working matrix (lower triangle)
  Vec rpack_;             ///< its factor R, upper triangular packed by rows
  std::unique_ptr<Qp> qp_;
};

}  // namespace lipmpcc::sqp
