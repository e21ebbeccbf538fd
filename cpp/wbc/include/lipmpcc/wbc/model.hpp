// WbcModel: the immutable robot model of the whole-body QP.
//
// Built once from the MJCF file the simulator loads (Pinocchio's MJCF parser, free-flyer root), it
// holds the Pinocchio model (behind a pointer, so that this header stays free of Pinocchio), the
// frame ids of the soles and torso, the actuation matrix B (nv x nu), the motor bounds, the arm
// joints and the sole geometry. Copies share the Pinocchio model; nothing here changes after
// construction.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "lipmpcc/wbc/types.hpp"

namespace lipmpcc::wbc {

namespace detail {
struct PinocchioModel;  // defined in src/pinocchio_model.hpp (Pinocchio translation units only)
}

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
  const std::vector<int>& armIdxV() const { return arm_idx_v_; }
  /// Joint damping [N m s/rad] per velocity coordinate (from the MJCF), zero on the base.
  const Vec& damping() const { return damping_; }
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
  /// Neutral configuration (free-flyer at the origin, identity quaternion x,y,z,w).
  const Vec& neutral() const { return q_neutral_; }

 private:
  WbcModelSpec spec_;
  std::shared_ptr<const detail::PinocchioModel> pin_;
  int nq_ = 0;
  int nv_ = 0;
  double mass_ = 0.0;
  Mat B_, B_pinv_, N_T_;
  Vec u_min_, u_max_;
  std::vector<int> arm_idx_q_, arm_idx_v_;
  Vec damping_;
  std::vector<int> spring_idx_q_, spring_idx_v_;
  std::array<std::size_t, kNumFeet> sole_frames_{0, 0};
  std::size_t torso_frame_ = 0;
  std::vector<std::string> joint_names_;
  std::vector<int> joint_idx_q_, joint_idx_v_, joint_nq_;
  Vec q_lower_, q_upper_, q_neutral_;
};

}  // namespace lipmpcc::wbc
