// WbcModel: the immutable robot model of the whole-body QP.
//
// Built once from the MJCF file the simulator loads (Pinocchio's MJCF parser), it holds the
// Pinocchio model (behind a pointer, so that this header stays free of Pinocchio), the frame ids of
// the soles and torso, the actuation matrix B (nv x nu), the motor bounds, the arm joints, the
// springs, the sole geometry and the closed kinematic loops. Copies share the Pinocchio model;
// nothing here changes after construction.
//
// Floating base: a free joint (Pinocchio free-flyer), or 3 slide joints + a ball joint on the root
// body (a Pinocchio composite joint, as in the Digit v3 MJCF); a root body without a joint gets a
// free-flyer. Either way the base quaternion (x, y, z, w) sits at q[baseQuaternionIdx() ..+4].
//
// Closed loops: every `<equality connect>` of the MJCF (a Pinocchio point-anchor constraint) is a
// loop closure whose two anchor points must coincide (3 rows). With LoopFormulation::kEliminate the
// loop-dependent velocity coordinates (chosen once among the unactuated, non-base ones) are
// eliminated and the QP runs in the independent ones (qpCoordinates()).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "lipmpcc/wbc/types.hpp"

namespace lipmpcc::wbc {

namespace detail {
struct PinocchioModel;  // defined in src/pinocchio_model.hpp (Pinocchio translation units only)
}

/// One loop closure: two points, each fixed to a joint, that must coincide.
struct LoopClosure {
  std::string joint1;              ///< Pinocchio joint carrying the first anchor
  std::string joint2;              ///< Pinocchio joint carrying the second anchor
  Vec3 anchor1 = Vec3::Zero();     ///< [m] first anchor in joint1's frame
  Vec3 anchor2 = Vec3::Zero();     ///< [m] second anchor in joint2's frame
  std::size_t frame1 = 0;          ///< operational frames placed at the anchors
  std::size_t frame2 = 0;
};

/// A small constant matrix stored by rows with its exact non-zeros only (N^T and B^+ are scaled
/// selections on most robots). Products with it skip exact zeros: same values as the dense product
/// up to the order of the floating-point sums.
struct SparseRows {
  Eigen::Index rows = 0, cols = 0;
  std::vector<int> start{0};  ///< row i: entries [start[i], start[i + 1])
  std::vector<int> col;
  std::vector<double> val;

  static SparseRows from(const Mat& S) {
    SparseRows r;
    r.rows = S.rows();
    r.cols = S.cols();
    for (Eigen::Index i = 0; i < S.rows(); ++i) {
      for (Eigen::Index k = 0; k < S.cols(); ++k)
        if (S(i, k) != 0.0) {
          r.col.push_back(static_cast<int>(k));
          r.val.push_back(S(i, k));
        }
      r.start.push_back(static_cast<int>(r.col.size()));
    }
    return r;
  }

  /// out = scale * S X, X given by its rows (X.rows() == cols).
  template <typename XType, typename OutType>
  void product(const Eigen::MatrixBase<XType>& X, double scale, const Eigen::MatrixBase<OutType>& out_) const {
    auto& out = const_cast<Eigen::MatrixBase<OutType>&>(out_);
    for (Eigen::Index i = 0; i < rows; ++i) {
      const auto ii = static_cast<std::size_t>(i);
      if (start[ii] == start[ii + 1]) {
        out.row(i).setZero();
        continue;
      }
      const auto p0 = static_cast<std::size_t>(start[ii]);
      out.row(i) = (scale * val[p0]) * X.row(col[p0]);
      for (auto p = p0 + 1; p < static_cast<std::size_t>(start[ii + 1]); ++p)
        out.row(i) += (scale * val[p]) * X.row(col[p]);
    }
  }
};

/// The acceleration coordinates the QP works in, and the actuation expressed in them. Without
/// loop elimination these are the nv velocity coordinates; with it, the independent ones
/// (qdd[independent] = a).
struct QpCoordinates {
  int n = 0;                 ///< number of acceleration variables of the QP
  Mat B;                     ///< (n x nu) actuation in these coordinates
  Mat B_pinv;                ///< (nu x n) its pseudo-inverse
  Mat N_T;                   ///< (n_unact x n) rows spanning the left null space of B
  std::vector<int> arm_idx;  ///< arm joints among the n coordinates
  std::vector<int> limit_idx;  ///< the range-limited actuated joints among the n coordinates
  SparseRows B_pinv_rows;    ///< B_pinv and N_T by rows (the QP assembly's products)
  SparseRows N_T_rows;
};

class WbcModel {
 public:
  /// Parses spec.mjcf_path and resolves every name. Throws std::invalid_argument naming the
  /// missing body/joint/site, or std::runtime_error if the file cannot be parsed.
  explicit WbcModel(const WbcModelSpec& spec);
  ~WbcModel();
  WbcModel(const WbcModel&);
  WbcModel& operator=(const WbcModel&);

  const WbcModelSpec& spec() const { return spec_; }
  const detail::PinocchioModel& pin() const { return *pin_; }

  int nq() const { return nq_; }
  int nv() const { return nv_; }
  int nu() const { return static_cast<int>(u_min_.size()); }
  int nArm() const { return static_cast<int>(arm_idx_v_.size()); }
  double mass() const { return mass_; }

  /// Actuation matrix B (nv x nu): generalised force = B u.
  const Mat& actuation() const { return B_; }
  /// Moore-Penrose pseudo-inverse of B (nu x nv): u = B^+ (M qdd + h - J^T f).
  const Mat& actuationPinv() const { return B_pinv_; }
  /// Rows spanning the left null space of B (n_unact x nv): the unactuated dynamics rows.
  const Mat& unactuatedRows() const { return N_T_; }
  const Vec& uMin() const { return u_min_; }
  const Vec& uMax() const { return u_max_; }

  const std::vector<int>& armIdxQ() const { return arm_idx_q_; }
  /// Actuated joints with a finite position range: their q and v indices and the range [rad or m].
  const std::vector<int>& limitIdxQ() const { return limit_idx_q_; }
  const std::vector<int>& limitIdxV() const { return limit_idx_v_; }
  const Vec& limitLower() const { return limit_lower_; }
  const Vec& limitUpper() const { return limit_upper_; }
  int nLimits() const { return static_cast<int>(limit_idx_v_.size()); }
  const std::vector<int>& armIdxV() const { return arm_idx_v_; }
  /// Joint damping [N m s/rad] per velocity coordinate (from the MJCF), zero on the base.
  const Vec& damping() const { return damping_; }
  /// Dry joint friction [N m] per velocity coordinate (zeros when none).
  const Vec& frictionloss() const { return frictionloss_; }
  bool hasFrictionloss() const { return has_frictionloss_; }
  const std::vector<int>& springIdxQ() const { return spring_idx_q_; }
  const std::vector<int>& springIdxV() const { return spring_idx_v_; }

  std::size_t soleFrame(int foot) const { return sole_frames_[static_cast<std::size_t>(foot)]; }
  std::size_t torsoFrame() const { return torso_frame_; }

  /// Names of the joints (without "universe"), in Pinocchio order, with their first q and v index.
  const std::vector<std::string>& jointNames() const { return joint_names_; }
  const std::vector<int>& jointIdxQ() const { return joint_idx_q_; }
  const std::vector<int>& jointIdxV() const { return joint_idx_v_; }
  const std::vector<int>& jointNq() const { return joint_nq_; }
  const Vec& lowerPositionLimit() const { return q_lower_; }
  const Vec& upperPositionLimit() const { return q_upper_; }
  /// Neutral configuration (base at the origin, identity quaternions x,y,z,w).
  const Vec& neutral() const { return q_neutral_; }

  /// Index of the base quaternion (x, y, z, w) in q.
  int baseQuaternionIdx() const { return base_quat_idx_; }
  /// First of the 6 velocity coordinates of the floating base.
  int baseIdxV() const { return base_idx_v_; }
  /// "free joint", "slide+ball" or "added free-flyer" (the root body had no joint).
  const std::string& baseKind() const { return base_kind_; }

  /// Closed loops (empty for a tree-structured model).
  const std::vector<LoopClosure>& loops() const { return loops_; }
  int nLoopRows() const { return 3 * static_cast<int>(loops_.size()); }
  /// Passive springs held rigid by a holonomic row (SpringModel::kRigid): indices into
  /// springIdxQ()/springIdxV().
  const std::vector<int>& rigidSprings() const { return rigid_springs_; }
  /// Holonomic rows: 3 per loop, then one per rigid spring (J_loop in DynamicsTerms).
  int nConstraintRows() const { return nLoopRows() + static_cast<int>(rigid_springs_.size()); }
  /// True when the QP eliminates the constraint-dependent accelerations (kEliminate, rows present).
  bool eliminatesLoops() const { return !dependent_idx_v_.empty(); }
  /// Velocity coordinates solved from the loop rows (ascending), and the others (ascending).
  const std::vector<int>& dependentIdxV() const { return dependent_idx_v_; }
  const std::vector<int>& independentIdxV() const { return independent_idx_v_; }
  const QpCoordinates& qpCoordinates() const { return qp_coords_; }

 private:
  /// Picks the loop-dependent coordinates at the loop reference configuration and builds the
  /// QP's coordinates (kEliminate).
  void chooseLoopCoordinates();

  WbcModelSpec spec_;
  std::shared_ptr<const detail::PinocchioModel> pin_;
  int nq_ = 0;
  int nv_ = 0;
  double mass_ = 0.0;
  Mat B_, B_pinv_, N_T_;
  Vec u_min_, u_max_;
  std::vector<int> arm_idx_q_, arm_idx_v_;
  std::vector<int> limit_idx_q_, limit_idx_v_;
  Vec limit_lower_, limit_upper_;
  Vec damping_;
  Vec frictionloss_;
  bool has_frictionloss_ = false;
  std::vector<int> spring_idx_q_, spring_idx_v_;
  std::array<std::size_t, kNumFeet> sole_frames_{0, 0};
  std::size_t torso_frame_ = 0;
  std::vector<std::string> joint_names_;
  std::vector<int> joint_idx_q_, joint_idx_v_, joint_nq_;
  Vec q_lower_, q_upper_, q_neutral_;
  int base_quat_idx_ = 3;
  int base_idx_v_ = 0;  ///< first velocity coordinate of the base (6 of them)
  std::string base_kind_;
  std::vector<LoopClosure> loops_;
  std::vector<int> rigid_springs_;
  std::vector<int> dependent_idx_v_, independent_idx_v_;
  QpCoordinates qp_coords_;
};

}  // namespace lipmpcc::wbc
