// Elimination of the loop-dependent accelerations (LoopFormulation::kEliminate). Eigen only.
//
// The loop rows J_loop qdd + gamma = 0 split the velocity coordinates into dependent (d, as many
// as loop rows, chosen once by WbcModel) and independent (i) ones:
//   J_d qdd_d + J_i qdd_i + gamma = 0   =>   qdd_d = G qdd_i + g0,  G = -J_d^-1 J_i,  g0 = -J_d^-1 gamma,
// i.e. qdd = Z a + z0 with a = qdd_i. Every task Jacobian J becomes J Z (= J_i + J_d G) with the
// drift J_d g0 added, and the dynamics projected on the loops' admissible motions,
//   Z^T (M qdd + h - J_c^T w) = Z^T B u   (the loop forces J_loop^T lambda drop out, Z^T J_loop^T = 0),
// keeps the QP of a tree-structured robot with n_i coordinates. Z^T B is B's independent rows
// because dependent coordinates are unactuated. The loop forces follow from the dependent rows:
//   J_d^T lambda = (M qdd + h - J_c^T w - B u)_d.
#pragma once

#include <Eigen/LU>
#include <vector>

#include "lipmpcc/wbc/dynamics.hpp"
#include "lipmpcc/wbc/model.hpp"

namespace lipmpcc::wbc {

/// Workspace of one elimination (one per solver). Every buffer keeps its capacity across ticks.
///
/// G is very sparse on real robots (a loop's dependent coordinates move with the few joints of its
/// own leg): its exact non-zeros are listed per tick, by column (CSC) and by row (CSR), and every
/// product with G or G^T runs over them only. The skipped terms are exact zeros, so the results
/// are those of the dense products up to the order of the floating-point sums.
struct LoopReduction {
  Eigen::PartialPivLU<Mat> lu;  ///< of J_d
  Mat G;                        ///< (n_d x n_i) qdd_d = G a + g0
  Vec g0;                       ///< (n_d)
  Mat Jd;                       ///< scratch: J_d (n_d x n_d)
  Mat Ji;                       ///< scratch: the non-zero columns of J_i
  Mat Gc;                       ///< scratch: J_d^-1 times those columns
  std::vector<int> g_cols;      ///< independent coordinates whose column of J_i is not zero
  std::vector<int> csc_start;   ///< per entry of g_cols: its non-zeros in csc_row[start[c], start[c+1])
  std::vector<int> csc_row;     ///< row (dependent coordinate) of each non-zero of G, by column
  std::vector<int> csr_start;   ///< per row k of G: its non-zeros in csr_col[start[k], start[k+1])
  std::vector<int> csr_col;     ///< column (independent coordinate) of each non-zero of G, by row
  Mat MZ;                       ///< scratch: M Z (nv x n_i), rows in the velocity order
  Vec hz;                       ///< scratch: h + M z0 (nv)
  Vec rd;                       ///< scratch: dependent rows of the dynamics residual
  double rcond = 0.0;           ///< reciprocal condition estimate of J_d at the last reduction
};

/// Smallest reciprocal condition number of J_d accepted by reduceLoops.
constexpr double kMinLoopRcond = 1e-10;

/// Fills `reduced` (the terms in the QP's coordinates a) from the full-coordinate `full` terms.
/// Returns false (nothing usable) when J_d is singular at this configuration.
bool reduceLoops(const WbcModel& model, const DynamicsTerms& full, LoopReduction& ws, DynamicsTerms& reduced);

/// Full accelerations qdd = Z a + z0 from the QP's accelerations a.
void expandAccelerations(const WbcModel& model, const LoopReduction& ws, const Eigen::Ref<const Vec>& a,
                         Vec& qdd);

/// Loop forces lambda from the dependent rows of residual = M qdd + h - J_c^T w - B u.
void loopForcesFromResidual(const WbcModel& model, LoopReduction& ws, const Eigen::Ref<const Vec>& residual,
                            Vec& lambda);

}  // namespace lipmpcc::wbc
