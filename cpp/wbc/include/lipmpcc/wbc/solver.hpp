// WbcSolver: the mutable workspace of the whole-body QP (Pinocchio data, one persistent QP solver
// (proxsuite or DAQP) per support mode, last torques, failure counter) around an immutable WbcModel + WbcParams.
#pragma once

#include <array>
#include <memory>

#include "lipmpcc/wbc/dynamics.hpp"
#include "lipmpcc/wbc/loop_reduction.hpp"
#include "lipmpcc/wbc/model.hpp"
#include "lipmpcc/wbc/qp.hpp"
#include "lipmpcc/wbc/qp_solver.hpp"
#include "lipmpcc/wbc/worker.hpp"

namespace lipmpcc::wbc {

class WbcSolver {
 public:
  /// Throws std::invalid_argument on inconsistent parameters.
  WbcSolver(const WbcModel& model, const WbcParams& params);
  WbcSolver(const WbcSolver&) = delete;
  WbcSolver& operator=(const WbcSolver&) = delete;

  /// One control tick. q: Pinocchio configuration (nq, base quaternion x y z w at
  /// model.baseQuaternionIdx(), normalised here), v: Pinocchio velocity (nv).
  /// Throws std::invalid_argument("<argument>: <what was expected>") on invalid input only (sizes, NaN/inf, a zero quaternion, a
  /// reference rotation that is not a rotation, max_normal_force < min_normal_force). A QP failure (any status other than
  /// solved, a non-finite solution, a solver exception) never throws: the output then holds the
  /// fallback efforts u = clip(u_last - fallback_damping * B^T v, u_min, u_max), with u_last the
  /// efforts of the last successful solve (zero before the first), used_fallback is set and the
  /// failure counter grows.
  WbcOutput solve(const Eigen::Ref<const Vec>& q, const Eigen::Ref<const Vec>& v,
                  const WbcReference& ref);
  /// Same, writing into `out` (no allocation once sizes are settled).
  void solveInto(const Eigen::Ref<const Vec>& q, const Eigen::Ref<const Vec>& v,
                 const WbcReference& ref, WbcOutput& out);

  /// Starts the first stage of the next tick: the dynamics terms of (q, v) (Pinocchio pass, spring
  /// damping, friction, loop elimination). A solve() with the same q and v (equal values) then
  /// skips that stage; its results are identical to a solve() without prepare(). With `async`
  /// the stage runs on a worker thread (created on first use) while the caller goes on; every
  /// other member waits for it. Never throws: invalid input is left for solve() to report.
  void prepare(const Eigen::Ref<const Vec>& q, const Eigen::Ref<const Vec>& v, bool async);

  /// Dynamics terms at (q, v) without solving (the quaternion is normalised). Throws
  /// std::invalid_argument on wrong sizes or non-finite input.
  const DynamicsTerms& evaluate(const Eigen::Ref<const Vec>& q, const Eigen::Ref<const Vec>& v);

  /// Forgets warm starts, last efforts and the failure count.
  void reset();

  long qpFailures() const { return failures_; }
  const WbcModel& model() const { return model_; }
  const WbcParams& params() const { return params_; }
  /// The QP and the dynamics terms of the last tick (for tests and debugging); the reduced terms
  /// are those the QP was built from when loops are eliminated.
  const QpProblem& lastProblem() const { return qp_; }
  const DynamicsTerms& lastTerms() const { sync(); return terms_; }
  const DynamicsTerms& lastReducedTerms() const { sync(); return reduced_; }
  const Vec& lastEfforts() const { return u_last_; }

 private:
  /// The first stage of a tick at (q, v) (finite, sizes checked): normalised q in q_work_, terms_,
  /// and with eliminated loops reduction_ and reduced_. Returns false when the loops are singular.
  /// Throws std::invalid_argument on a zero base quaternion.
  bool computeTerms(const Eigen::Ref<const Vec>& q, const Eigen::Ref<const Vec>& v);
  /// prepare()'s job: computeTerms on prep_q_, prep_v_.
  void runPrepared() noexcept;
  /// Waits for a prepare() running on the worker. In a process forked since the worker started,
  /// forgets it (its thread is not there; a new one is made on the next prepare) and its result.
  void sync() const {
    if (!worker_) return;
    if (worker_->inThisProcess()) {
      worker_->wait();
      return;
    }
    (void)worker_.release();  // not destroyed: joining a thread of the parent process would hang
    prep_valid_ = false;
  }
  /// Rigid passive springs: their rows ask qdd_s = -spring_damping_gain * qdot_s.
  void applySpringDamping(const Eigen::Ref<const Vec>& v);
  /// Spring joint torques: -k (q - q_ref), plus the rows' force for rigid passive springs.
  void springTorques(const Eigen::Ref<const Vec>& q, const Eigen::Ref<const Vec>& rigid_lambda, Vec& torques) const;

  const WbcModel model_;
  const WbcParams params_;
  DynamicsEvaluator dynamics_;
  DynamicsTerms terms_;
  DynamicsTerms reduced_;       // terms in the independent accelerations (eliminated loops)
  LoopReduction reduction_;
  Vec loop_residual_;
  Vec lambda_;  // holonomic-row forces of the last solve (loops, then rigid springs)
  QpProblem qp_;
  QpSolution sol_;
  std::array<std::unique_ptr<QpSolver>, 4> solvers_;  // one per support mode (flight, left, right, double)
  int last_mode_ = -1;
  Vec q_work_;
  Vec u_last_;
  long failures_ = 0;
  // prepare(): the state it was given, whether its stage is usable, its result and time [us]
  Vec prep_q_, prep_v_;
  mutable bool prep_valid_ = false;
  bool prep_loops_ok_ = false;
  double prep_time_us_ = 0.0;
  mutable std::unique_ptr<Worker> worker_;  // last member: its thread stops before the workspace goes
};

}  // namespace lipmpcc::wbc
