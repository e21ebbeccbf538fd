// Kinematic and dynamic terms of one tick, computed in a single Pinocchio pass.
// The struct is plain Eigen so that the QP assembly does not depend on Pinocchio.
#pragma once

#include <memory>
#include <vector>

#include "lipmpcc/wbc/model.hpp"

namespace lipmpcc::wbc {

namespace detail {
struct PinocchioData;
}

/// Everything the QP needs about the current state (q, v). World-aligned axes throughout;
/// "drift" terms are accelerations at qdd = 0 (the J-dot v terms).
struct DynamicsTerms {
  Mat M;              ///< (nv x nv) joint-space inertia (armature included), symmetric.
  Vec h;              ///< (nv) C(q,v) v + g(q) - passive forces (damping, springs).
  std::array<Mat6x, kNumFeet> J_sole;       ///< (6 x nv) LOCAL_WORLD_ALIGNED frame Jacobians.
  std::array<Vec6, kNumFeet> drift_sole;    ///< classical acceleration [lin; ang] at qdd = 0.
  std::array<Vec6, kNumFeet> vel_sole;      ///< frame velocity [lin; ang], world axes.
  std::array<Vec3, kNumFeet> p_sole;        ///< [m] sole positions.
  std::array<Mat3, kNumFeet> R_sole;        ///< sole orientations.
  Vec3 com = Vec3::Zero();
  Vec3 vcom = Vec3::Zero();
  Mat3x J_com;                              ///< (3 x nv)
  Vec3 drift_com = Vec3::Zero();
  Mat3 R_torso = Mat3::Identity();
  Vec3 w_torso = Vec3::Zero();              ///< [rad/s] world axes.
  Mat3x J_torso;                            ///< (3 x nv) angular rows.
  Vec3 drift_torso = Vec3::Zero();
  Mat3x A_ang;                              ///< (3 x nv) angular rows of the centroidal map.
  Vec3 k_com = Vec3::Zero();                ///< centroidal angular momentum A_ang v.
  Vec3 drift_k = Vec3::Zero();              ///< dA_ang v.
  /// Holonomic rows (WbcModel::nConstraintRows()): 3 per loop (WbcModel::loops() order), where
  /// J_loop qdd + gamma_loop is the relative acceleration of the two anchors (world axes), then one
  /// per rigid passive spring (its acceleration). loop_residual [m]: the anchors' offset (anchor 1
  /// - anchor 2), 3 per loop. No rows for a tree-structured model with compliant springs.
  Mat J_loop;
  Vec gamma_loop;
  Vec loop_residual;
  /// Extra holonomic equalities J_extra qdd + gamma_extra = 0 whose forces J_extra^T lambda
  /// enter the dynamics: the loop rows with LoopFormulation::kMultipliers, else none.
  Mat J_extra;
  Vec gamma_extra;
  /// Metric of the qdd regularisation in these coordinates: 0.5 reg (a^T Q a) + reg q_g^T a.
  /// Empty: identity and zero (full coordinates). After loop elimination Q = Z^T Z, q_g = Z^T z0,
  /// so that the regularisation is still reg |qdd|^2 on the full accelerations.
  Mat qdd_metric;
  Vec qdd_metric_g;
  Mat6x J_sole_scratch;  ///< workspace (torso Jacobian), not an output.
};

/// Owns the Pinocchio data and fills DynamicsTerms.
class DynamicsEvaluator {
 public:
  explicit DynamicsEvaluator(const WbcModel& model);
  ~DynamicsEvaluator();
  DynamicsEvaluator(const DynamicsEvaluator&) = delete;
  DynamicsEvaluator& operator=(const DynamicsEvaluator&) = delete;

  /// q: Pinocchio configuration (quaternion normalised by the caller), v: Pinocchio velocity.
  void compute(const Eigen::Ref<const Vec>& q, const Eigen::Ref<const Vec>& v, DynamicsTerms& out);

  /// Constraint Jacobian (nConstraintRows x nv) and loop residual [m] at configuration q (no
  /// velocity terms); used once to choose the constraint-dependent coordinates.
  void loopKinematics(const Eigen::Ref<const Vec>& q, Mat& J_loop, Vec& residual);

 private:
  const WbcModel& model_;
  std::unique_ptr<detail::PinocchioData> data_;
  bool zero_once_ = false;         ///< frame Jacobian buffers keep their zero columns across ticks
  std::vector<Mat6x> J_anchor_;    ///< frame Jacobians of the loop anchors (2 per loop)
};

}  // namespace lipmpcc::wbc
