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
using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat3 = Eigen::Matrix3d;
using Mat6x = Eigen::Matrix<double, 6, Eigen::Dynamic>;
using Mat3x = Eigen::Matrix<double, 3, Eigen::Dynamic>;

/// How closed kinematic loops (MJCF `<equality connect>`) enter the whole-body QP.
enum class LoopFormulation : int {
  /// Eliminate the loop-dependent accelerations: qdd = Z a + z0 with Z spanning the null space of
  /// the loop Jacobian; the QP runs in the independent accelerations a (smaller, faster).
  kEliminate = 0,
  /// Keep every acceleration and add the loop rows J_loop qdd + gamma = 0 as equalities, with the
  /// loop forces J_loop^T lambda as extra QP variables (the textbook form; slower).
  kMultipliers = 1,
};

/// How passive springs (a joint with a stiffness and no motor) enter the whole-body QP. Their
/// known torque -k (q - q_ref) is in h either way.
enum class SpringModel : int {
  /// The spring joint moves freely under its known torque (its acceleration follows from the
  /// dynamics). Exact, but the QP then sees the fast spring mode: at a touch-down with an unloaded
  /// spring it can barely use the ground until the spring has deflected.
  kCompliant = 0,
  /// For the controller the spring is a stiff joint: its acceleration is held at zero by a
  /// holonomic row (like a loop row) whose force adds to the known spring torque. The simulated
  /// spring deflects quasi-statically under the load the QP plans (the usual choice for Cassie
  /// and Digit whole-body controllers).
  kRigid = 1,
};

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
  /// [m] centre of each sole rectangle (x, y) in its sole frame (e.g. a sole site that is not
  /// at the centre of the foot's collision box).
  std::array<Vec2, kNumFeet> sole_cop_centers{Vec2::Zero(), Vec2::Zero()};
  double friction = 0.7;                     ///< friction-pyramid coefficient (dimensionless).
  /// Actuation: actuator k drives joint `actuated_joints[k]` with generalised force
  /// actuation_gains[k] * u_k (MuJoCo: gear * gain). Bounds u_min <= u <= u_max.
  std::vector<std::string> actuated_joints;
  Vec actuation_gains;
  Vec u_min;
  Vec u_max;
  std::vector<std::string> arm_joints;      ///< joints held at a constant posture.
  /// [m/s^2] gravity (MuJoCo opt.gravity); empty: Pinocchio's default (0, 0, -9.81).
  Vec gravity;
  /// [N m] dry friction per velocity coordinate (nv, MuJoCo dof_frictionloss); empty: none. The
  /// QP compensates it as a smooth Coulomb force f tanh(v / v_f) in h
  /// (WbcParams::friction_compensation_velocity).
  Vec frictionloss;
  /// [N m s/rad] damping per velocity coordinate (nv, MuJoCo dof_damping); empty: the damping
  /// Pinocchio reads from the MJCF (which skips ball joints).
  Vec damping;
  /// Springs on 1-DoF joints: tau = -k (q - q_ref). Those without a motor are passive springs
  /// (spring_model).
  std::vector<std::string> spring_joints;
  Vec spring_stiffness;                      ///< [N m/rad] or [N/m]
  Vec spring_reference;                      ///< [rad] or [m]
  /// Closed loops: every point-anchor (`<equality connect>`) constraint Pinocchio parses from the
  /// MJCF becomes 3 holonomic rows J_loop qdd + gamma = 0 (loop forces in the dynamics).
  LoopFormulation loop_formulation = LoopFormulation::kEliminate;
  SpringModel spring_model = SpringModel::kCompliant;
  /// Pinocchio configuration (nq) at which the loop-dependent coordinates are chosen (a standing
  /// pose, loops closed); empty: the model's neutral configuration.
  Vec loop_reference_configuration;
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

/// The dense QP solver of the whole-body QP.
enum class QpSolverKind : int {
  kProxsuite = 0,  ///< proxsuite 0.8 dense (ALM / interior point), warm-started from its previous result.
  kDaqp = 1,       ///< DAQP (dual active set, vendored C), warm-started from the previous working set.
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
  /// [1/s] rigid passive springs (SpringModel::kRigid): qdd_s = -gain * qdot_s, so that the
  /// controller damps the (otherwise undamped) spring mode it does not model.
  double spring_damping_gain = 0.0;
  /// [rad/s] velocity scale v_f of the dry-friction compensation f tanh(v / v_f) (> 0).
  double friction_compensation_velocity = 0.02;
  QpSolverKind qp_solver = QpSolverKind::kProxsuite;  ///< the QP solver.
  double qp_eps_abs = 1e-6;              ///< proxsuite absolute tolerance; DAQP primal tolerance.
  int qp_max_iter = 50;                  ///< proxsuite outer and inner iteration limits (DAQP: 20 x this).
  double fallback_damping = 1.0;         ///< [N m s/rad] fallback u = u_last - d * (B^T v).
  /// [s] horizon h of the joint position limit rows: every actuated joint with a finite range keeps
  /// q + v h + qdd h^2 / 2 within it; 0: no such rows.
  double joint_limit_horizon = 0.0;
  /// The yaw rows of each sole's contact wrench cone (qp.hpp): less yaw moment as the CoP nears an edge.
  bool torsion_cone = false;
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
  kSingularLoops = 8,  ///< the loop Jacobian is singular in the dependent coordinates (no QP built).
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
  /// (3 per loop) [N] loop-closure forces lambda, world axes: M qdd + h_0 = B u + J_c^T w +
  /// J_loop^T lambda + S_s^T spring_torques, with h_0 the bias forces without the springs. Zero
  /// after a fallback, empty for a tree-structured model.
  Vec loop_forces;
  /// (one per spring joint) [N m] or [N] torque of each spring joint: -k (q - q_ref), plus the
  /// holding torque the QP plans for a rigid passive spring (SpringModel::kRigid).
  Vec spring_torques;
  QpStatus status = QpStatus::kNotRun;
  int iterations = 0;
  double solve_time_us = 0.0;   ///< QP update + solve.
  double tick_time_us = 0.0;    ///< whole tick: dynamics terms, QP assembly, solve, torques.
  bool used_fallback = false;
  TaskErrors errors;
};

}  // namespace lipmpcc::wbc
