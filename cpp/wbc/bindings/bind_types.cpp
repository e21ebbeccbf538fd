// Bindings of the plain data types: WbcModelSpec, TaskGains, WbcParams, WbcReference, QpStatus,
// TaskErrors, WbcOutput.
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "lipmpcc/wbc/types.hpp"

namespace py = pybind11;

namespace lipmpcc::wbc::bindings {

void bindTypes(py::module_& m) {
  py::enum_<LoopFormulation>(m, "LoopFormulation")
      .value("eliminate", LoopFormulation::kEliminate)
      .value("multipliers", LoopFormulation::kMultipliers);
  py::enum_<SpringModel>(m, "SpringModel")
      .value("compliant", SpringModel::kCompliant)
      .value("rigid", SpringModel::kRigid);

  py::class_<WbcModelSpec>(m, "WbcModelSpec")
      .def(py::init<>())
      .def_readwrite("mjcf_path", &WbcModelSpec::mjcf_path)
      .def_readwrite("foot_bodies", &WbcModelSpec::foot_bodies)
      .def_readwrite("sole_sites", &WbcModelSpec::sole_sites)
      .def_readwrite("sole_offsets", &WbcModelSpec::sole_offsets)
      .def_readwrite("torso_body", &WbcModelSpec::torso_body)
      .def_readwrite("foot_half_length", &WbcModelSpec::foot_half_length)
      .def_readwrite("foot_half_width", &WbcModelSpec::foot_half_width)
      .def_readwrite("sole_cop_centers", &WbcModelSpec::sole_cop_centers)
      .def_readwrite("friction", &WbcModelSpec::friction)
      .def_readwrite("actuated_joints", &WbcModelSpec::actuated_joints)
      .def_readwrite("actuation_gains", &WbcModelSpec::actuation_gains)
      .def_readwrite("u_min", &WbcModelSpec::u_min)
      .def_readwrite("u_max", &WbcModelSpec::u_max)
      .def_readwrite("arm_joints", &WbcModelSpec::arm_joints)
      .def_readwrite("damping", &WbcModelSpec::damping)
      .def_readwrite("frictionloss", &WbcModelSpec::frictionloss)
      .def_readwrite("gravity", &WbcModelSpec::gravity)
      .def_readwrite("spring_joints", &WbcModelSpec::spring_joints)
      .def_readwrite("spring_stiffness", &WbcModelSpec::spring_stiffness)
      .def_readwrite("spring_reference", &WbcModelSpec::spring_reference)
      .def_readwrite("loop_formulation", &WbcModelSpec::loop_formulation)
      .def_readwrite("spring_model", &WbcModelSpec::spring_model)
      .def_readwrite("loop_reference_configuration", &WbcModelSpec::loop_reference_configuration);

  py::class_<TaskGains>(m, "TaskGains")
      .def(py::init<>())
      .def_readwrite("weight", &TaskGains::weight)
      .def_readwrite("kp", &TaskGains::kp)
      .def_readwrite("kd", &TaskGains::kd);

  py::class_<ScalarTaskGains>(m, "ScalarTaskGains")
      .def(py::init<>())
      .def_readwrite("weight", &ScalarTaskGains::weight)
      .def_readwrite("kp", &ScalarTaskGains::kp)
      .def_readwrite("kd", &ScalarTaskGains::kd);

  py::enum_<QpSolverKind>(m, "QpSolverKind")
      .value("proxsuite", QpSolverKind::kProxsuite)
      .value("daqp", QpSolverKind::kDaqp);

  py::class_<WbcParams>(m, "WbcParams")
      .def(py::init<>())
      .def_readwrite("com", &WbcParams::com)
      .def_readwrite("torso", &WbcParams::torso)
      .def_readwrite("swing_position", &WbcParams::swing_position)
      .def_readwrite("swing_orientation", &WbcParams::swing_orientation)
      .def_readwrite("arm_posture", &WbcParams::arm_posture)
      .def_readwrite("angular_momentum_weight", &WbcParams::angular_momentum_weight)
      .def_readwrite("angular_momentum_kd", &WbcParams::angular_momentum_kd)
      .def_readwrite("qdd_regularization", &WbcParams::qdd_regularization)
      .def_readwrite("force_regularization", &WbcParams::force_regularization)
      .def_readwrite("min_normal_force", &WbcParams::min_normal_force)
      .def_readwrite("cop_safety_factor", &WbcParams::cop_safety_factor)
      .def_readwrite("contact_velocity_gain", &WbcParams::contact_velocity_gain)
      .def_readwrite("spring_damping_gain", &WbcParams::spring_damping_gain)
      .def_readwrite("friction_compensation_velocity", &WbcParams::friction_compensation_velocity)
      .def_readwrite("qp_solver", &WbcParams::qp_solver)
      .def_readwrite("qp_eps_abs", &WbcParams::qp_eps_abs)
      .def_readwrite("qp_max_iter", &WbcParams::qp_max_iter)
      .def_readwrite("fallback_damping", &WbcParams::fallback_damping)
      .def_readwrite("joint_limit_horizon", &WbcParams::joint_limit_horizon)
      .def_readwrite("torsion_cone", &WbcParams::torsion_cone);

  py::class_<WbcReference>(m, "WbcReference")
      .def(py::init<>())
      .def_readwrite("contact", &WbcReference::contact)
      .def_readwrite("com_pos", &WbcReference::com_pos)
      .def_readwrite("com_vel", &WbcReference::com_vel)
      .def_readwrite("com_acc", &WbcReference::com_acc)
      .def_readwrite("torso_rot", &WbcReference::torso_rot)
      .def_readwrite("torso_angvel", &WbcReference::torso_angvel)
      .def_readwrite("torso_angacc", &WbcReference::torso_angacc)
      .def_readwrite("foot_pos", &WbcReference::foot_pos)
      .def_readwrite("foot_vel", &WbcReference::foot_vel)
      .def_readwrite("foot_acc", &WbcReference::foot_acc)
      .def_readwrite("foot_rot", &WbcReference::foot_rot)
      .def_readwrite("foot_angvel", &WbcReference::foot_angvel)
      .def_readwrite("foot_angacc", &WbcReference::foot_angacc)
      .def_readwrite("arm_posture", &WbcReference::arm_posture)
      .def_readwrite("max_normal_force", &WbcReference::max_normal_force);

  py::enum_<QpStatus>(m, "QpStatus")
      .value("solved", QpStatus::kSolved)
      .value("max_iter_reached", QpStatus::kMaxIterReached)
      .value("primal_infeasible", QpStatus::kPrimalInfeasible)
      .value("dual_infeasible", QpStatus::kDualInfeasible)
      .value("solved_closest_primal_feasible", QpStatus::kSolvedClosestPrimalFeasible)
      .value("not_run", QpStatus::kNotRun)
      .value("non_finite", QpStatus::kNonFinite)
      .value("exception", QpStatus::kException)
      .value("singular_loops", QpStatus::kSingularLoops);
  m.def("status_name", [](QpStatus s) { return std::string(statusName(s)); });

  py::class_<TaskErrors>(m, "TaskErrors")
      .def_readonly("com_pos", &TaskErrors::com_pos)
      .def_readonly("com_vel", &TaskErrors::com_vel)
      .def_readonly("torso_rot", &TaskErrors::torso_rot)
      .def_readonly("torso_angvel", &TaskErrors::torso_angvel)
      .def_readonly("foot_pos", &TaskErrors::foot_pos)
      .def_readonly("foot_rot", &TaskErrors::foot_rot)
      .def_readonly("arm_posture", &TaskErrors::arm_posture)
      .def_readonly("angular_momentum", &TaskErrors::angular_momentum);

  py::class_<WbcOutput>(m, "WbcOutput")
      .def_readonly("tau", &WbcOutput::tau)
      .def_readonly("tau_joint", &WbcOutput::tau_joint)
      .def_readonly("qdd", &WbcOutput::qdd)
      .def_readonly("wrenches", &WbcOutput::wrenches)
      .def_readonly("loop_forces", &WbcOutput::loop_forces)
      .def_readonly("spring_torques", &WbcOutput::spring_torques)
      .def_readonly("status", &WbcOutput::status)
      .def_readonly("iterations", &WbcOutput::iterations)
      .def_readonly("solve_time_us", &WbcOutput::solve_time_us)
      .def_readonly("tick_time_us", &WbcOutput::tick_time_us)
      .def_readonly("used_fallback", &WbcOutput::used_fallback)
      .def_readonly("errors", &WbcOutput::errors);
}

}  // namespace lipmpcc::wbc::bindings
