// Plain data types of the whole-body QP: model specification, parameters, reference, output.
// Only Eigen here, so that every translation unit (Pinocchio, proxsuite, pybind11) can include it.
#pragma once

#include <Eigen/Core>
#include <array>
#include <limits>
#include <string>
#include <vector>

namespace lipmpcc::wbc {

using Vec = Eigen::VectorXd;
using Mat = Eigen::MatrixXd;
using Vec3 = Eigen::Vector3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat3 = Eigen::Matrix3d;
using Mat6x = Eigen::Matrix<double, 6, Eigen::Dynamic>;
using Mat3x = Eigen::Matrix<double, 3, Eigen::Dynamic>;

/// Foot indices used in every per-foot array.
enum Foot : int { kLeft = 0, kRight = 1 };
constexpr int kNumFeet = 2;

/// Everything needed to build a WbcModel. Names refer to the MJCF file.
struct WbcModelSpec {
  std::string mjcf_path;                     ///< MJCF file (same file the simulator loads).
  std::array<std::string, kNumFeet> foot_bodies;   ///< foot body names (left, right).
  /// Existing frames (MJCF sites) used as sole frames; empty -> an operational frame is added
  /// on the foot body at `sole_offsets` (identity rotation).
  std::array<std::string, kNumFeet> sole_sites;
  std::array<Vec3, kNumFeet> sole_offsets{Vec3::Zero(), Vec3::Zero()};  ///< [m] in foot body frame.
  std::string torso_body;                    ///< body whose orientation is tracked.
  double foot_half_length = 0.1;             ///< [m] sole rectangle half-extent along the sole x axis.
  double foot_half_width = 0.05;             ///< [m] sole rectangle half-extent along the sole y axis.
  double friction = 0.7;                     ///< friction-pyramid coefficient (dimensionless).
  /// Actuation: actuator k drives joint `actuated_joints[k]` with generalised force
  /// actuation_gains[k] * u_k (MuJoCo: gear * gain). Bounds u_min <= u <= u_max.
  std::vector<std::string> actuated_joints;
  Vec actuation_gains;
  Vec u_min;
  Vec u_max;
  std::vector<std::string> arm_joints;      ///< joints held at a constant posture.
  /// Passive springs on 1-DoF joints: tau = -k (q - q_ref). Joint damping is read from the MJCF.
  std::vector<std::string> spring_joints;
  Vec spring_stiffness;                      ///< [N m/rad] or [N/m]
  Vec spring_reference;                      ///< [rad] or [m]
};

/// Weight and PD gains of one 3-D task. Desired acceleration:
/// a* = a_ref + kp .* (x_ref - x) + kd .* (v_ref - v). Cost 0.5 * sum_i weight_i * (J a - a*)_i^2.
struct TaskGains {
  Vec3 weight = Vec3::Ones();
  Vec3 kp = Vec3::Zero();   ///< [1/s^2]
  Vec3 kd = Vec3::Zero();   ///< [1/s]
};

/// Scalar-weight PD task (arm posture).
struct ScalarTaskGains {
  double weight = 1.0;
  double kp = 0.0;
  double kd = 0.0;
};

/// Weights, gains, regularisation and solver settings. Immutable once a solver is built.
struct WbcParams {
  TaskGains com;
  TaskGains torso;
  TaskGains swing_position;
  TaskGains swing_orientation;
  ScalarTaskGains arm_posture;
  double angular_momentum_weight = 0.0;  ///< weight of the centroidal angular momentum damping task.
  double angular_momentum_kd = 0.0;      ///< [1/s] desired rate = -kd * k_G.
  double qdd_regularization = 1e-4;      ///< weight on |qdd|^2.
  double force_regularization = 1e-6;    ///< weight on |f|^2 (wrench components).
  double min_normal_force = 0.0;         ///< [N] lower bound of fz for a foot in contact.
  double cop_safety_factor = 0.9;        ///< CoP kept within this fraction of the sole half-extents.
  double contact_velocity_gain = 0.0;    ///< [1/s] no-slip rows: J qdd + Jdot v = -gain * J v.
  double qp_eps_abs = 1e-6;              ///< proxsuite absolute tolerance.
  int qp_max_iter = 50;                  ///< proxsuite outer and inner iteration limits.
  double fallback_damping = 1.0;         ///< [N m s/rad] fallback u = u_last - d * (B^T v).
};

/// Desired motion for one control tick. World frame everywhere. Swing-foot fields of a foot in
/// contact are ignored.
struct WbcReference {
  std::array<bool, kNumFeet> contact{true, true};
  Vec3 com_pos = Vec3::Zero();
  Vec3 com_vel = Vec3::Zero();
  Vec3 com_acc = Vec3::Zero();
  Mat3 torso_rot = Mat3::Identity();
  Vec3 torso_angvel = Vec3::Zero();
  Vec3 torso_angacc = Vec3::Zero();
  std::array<Vec3, kNumFeet> foot_pos{Vec3::Zero(), Vec3::Zero()};
  std::array<Vec3, kNumFeet> foot_vel{Vec3::Zero(), Vec3::Zero()};
  std::array<Vec3, kNumFeet> foot_acc{Vec3::Zero(), Vec3::Zero()};
  std::array<Mat3, kNumFeet> foot_rot{Mat3::Identity(), Mat3::Identity()};
  std::array<Vec3, kNumFeet> foot_angvel{Vec3::Zero(), Vec3::Zero()};
  std::array<Vec3, kNumFeet> foot_angacc{Vec3::Zero(), Vec3::Zero()};
  Vec arm_posture;  ///< [rad] one entry per arm joint.
  /// [N] upper bound on the normal force of each foot in contact (load ramps at touch-down).
  std::array<double, kNumFeet> max_normal_force{std::numeric_limits<double>::infinity(),
                                                std::numeric_limits<double>::infinity()};
};

/// QP outcome. kSolved is the only success.
enum class QpStatus : int {
  kSolved = 0,
  kMaxIterReached = 1,
  kPrimalInfeasible = 2,
  kDualInfeasible = 3,
  kSolvedClosestPrimalFeasible = 4,
  kNotRun = 5,
  kNonFinite = 6,   ///< solver reported success but the solution has NaN/inf.
  kException = 7,   ///< the solver threw.
};

const char* statusName(QpStatus s);

/// Task-space errors (reference minus measured), world frame.
struct TaskErrors {
  Vec3 com_pos = Vec3::Zero();     ///< [m]
  Vec3 com_vel = Vec3::Zero();     ///< [m/s]
  Vec3 torso_rot = Vec3::Zero();   ///< [rad] log3(R_ref R^T)
  Vec3 torso_angvel = Vec3::Zero();  ///< [rad/s]
  std::array<Vec3, kNumFeet> foot_pos{Vec3::Zero(), Vec3::Zero()};  ///< zero for a stance foot.
  std::array<Vec3, kNumFeet> foot_rot{Vec3::Zero(), Vec3::Zero()};
  Vec arm_posture;                 ///< [rad]
  Vec3 angular_momentum = Vec3::Zero();  ///< [kg m^2/s] centroidal angular momentum (measured).
};

/// Result of one control tick.
struct WbcOutput {
  Vec tau;         ///< (nu) actuator efforts u (MuJoCo ctrl for motor actuators).
  Vec tau_joint;   ///< (nv) generalised actuation force B u.
  Vec qdd;         ///< (nv) joint accelerations (zero after a fallback).
  Mat6x wrenches = Mat6x::Zero(6, kNumFeet);  ///< column per foot: [f; tau] at the sole, world axes.
  QpStatus status = QpStatus::kNotRun;
  int iterations = 0;
  double solve_time_us = 0.0;   ///< QP update + solve.
  double tick_time_us = 0.0;    ///< whole tick: dynamics terms, QP assembly, solve, torques.
  bool used_fallback = false;
  TaskErrors errors;
};

}  // namespace lipmpcc::wbc
