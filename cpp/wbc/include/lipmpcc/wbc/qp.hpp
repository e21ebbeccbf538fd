// Assembly of the whole-body QP from the dynamics terms (Eigen only).
//
// Variables  x = [qdd (n); w_c (6 per foot in contact, left first); lambda (extra equalities)],
// w_c = [f; tau] the contact wrench at the sole frame in world axes. qdd, M, h, the Jacobians, B,
// B^+ and N^T are in the QP's coordinates (WbcModel::qpCoordinates()): the nv velocity
// coordinates, or the n = nv - 3 n_loops independent ones when closed loops are eliminated (the
// terms then come from reduceLoops, loop_reduction.hpp, and the qdd regularisation uses their
// metric Z^T Z). With LoopFormulation::kMultipliers the loop rows are the extra equalities.
// Objective  0.5 x^T H x + g^T x = 0.5 sum_tasks |J_t qdd + drift_t - a*_t|^2_W + regularisation.
// Equalities A x = b, in this order:
//   N^T (M qdd + h - J_c^T w_c - J_e^T lambda) = 0      (unactuated rows of the dynamics)
//   J_c qdd + drift_c = -k_c J_c v                      (no slip, 6 rows per stance foot)
//   J_e qdd + gamma_e = 0                               (extra holonomic equalities)
// Inequalities l <= C x <= u, in this order:
//   per stance foot, with the wrench rotated into the sole frame (fx fy fz tx ty tz):
//     |fx| <= mu fz, |fy| <= mu fz (4 rows), |tx'| <= s W fz, |ty'| <= s L fz (4 rows, CoP),
//     |tz'| <= mu min(s L, s W) fz (2 rows), fz_min <= fz <= fz_max (1 row), with t' the moments
//     about the sole rectangle's centre c (spec.sole_cop_centers, in the sole frame):
//     t' = (tx - cy fz, ty + cx fz, tz - cx fy + cy fx); with WbcParams::torsion_cone, 8 more:
//     the yaw rows of the rectangle's contact wrench cone (Caron et al. 2015; <= 0):
//     +-tz' + s1 (sW fx' +- mu tx') + s2 (sL fy' +- mu ty') - mu (sL + sW) fz, the yaw moment
//     shrinking with the CoP's distance to the edges and the tangential force, to 0 at a corner
//   u_min - B^+ h <= B^+ (M qdd - J_c^T w_c - J_e^T lambda) <= u_max - B^+ h  (nu rows)
#pragma once

#include "lipmpcc/wbc/dynamics.hpp"
#include "lipmpcc/wbc/model.hpp"

namespace lipmpcc::wbc {

constexpr int kRowsPerContactInequality = 11;
constexpr int kTorsionConeRows = 8;  ///< with WbcParams::torsion_cone: after each contact's 11 rows.
constexpr double kInfinity = 1e20;  ///< proxsuite's "no bound".

/// Sizes and offsets of one support mode.
struct QpLayout {
  int nv = 0;
  int nu = 0;
  std::array<bool, kNumFeet> contact{false, false};
  std::array<int, kNumFeet> wrench_offset{-1, -1};  ///< column of each foot's wrench, -1 if swing.
  int n_contacts = 0;
  int n_unact = 0;   ///< unactuated dynamics rows.
  int n_extra = 0;   ///< extra equality rows (and multipliers).
  int extra_offset = 0;
  int n_var = 0;
  int n_eq = 0;
  int n_in = 0;
  int n_limits = 0;  ///< joint position limit rows (the last n_limits inequality rows)
  /// 0: flight, 1: left only, 2: right only, 3: double support.
  int mode() const { return (contact[0] ? 1 : 0) + (contact[1] ? 2 : 0); }
};

QpLayout makeLayout(const WbcModel& model, const std::array<bool, kNumFeet>& contact, int n_extra,
                    int n_limits = 0, bool torsion_cone = false);

/// The QP data of one tick (proxsuite dense form).
struct QpProblem {
  QpLayout layout;
  Mat H;
  Vec g;
  Mat A;
  Vec b;
  Mat C;
  Vec l;
  Vec u;
};

/// Fills `qp` (resizing only when the layout changes) and the task errors.
/// q must have a normalised quaternion.
void buildQp(const WbcModel& model, const WbcParams& params, const DynamicsTerms& terms,
             const WbcReference& ref, const Eigen::Ref<const Vec>& q, const Eigen::Ref<const Vec>& v,
             QpProblem& qp, TaskErrors& errors);

/// Motor efforts from a QP solution: u = B^+ (M qdd + h - J_c^T w - J_e^T lambda).
void recoverEfforts(const WbcModel& model, const DynamicsTerms& terms, const QpLayout& layout,
                    const Eigen::Ref<const Vec>& x, Vec& u);

/// Rotation error log3(R_ref R^T) in world axes [rad].
Vec3 rotationError(const Mat3& R_ref, const Mat3& R);

}  // namespace lipmpcc::wbc
