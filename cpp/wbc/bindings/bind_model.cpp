// Binding of WbcModel (immutable robot model).
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "lipmpcc/wbc/model.hpp"

namespace py = pybind11;

namespace lipmpcc::wbc::bindings {

void bindModel(py::module_& m) {
  py::class_<WbcModel>(m, "WbcModel")
      .def(py::init<const WbcModelSpec&>(), py::arg("spec"))
      .def_property_readonly("spec", &WbcModel::spec)
      .def_property_readonly("nq", &WbcModel::nq)
      .def_property_readonly("nv", &WbcModel::nv)
      .def_property_readonly("nu", &WbcModel::nu)
      .def_property_readonly("n_arm", &WbcModel::nArm)
      .def_property_readonly("mass", &WbcModel::mass)
      .def_property_readonly("actuation", &WbcModel::actuation)
      .def_property_readonly("actuation_pinv", &WbcModel::actuationPinv)
      .def_property_readonly("unactuated_rows", &WbcModel::unactuatedRows)
      .def_property_readonly("u_min", &WbcModel::uMin)
      .def_property_readonly("u_max", &WbcModel::uMax)
      .def_property_readonly("damping", &WbcModel::damping)
      .def_property_readonly("frictionloss", &WbcModel::frictionloss)
      .def_property_readonly("arm_idx_q", &WbcModel::armIdxQ)
      .def_property_readonly("arm_idx_v", &WbcModel::armIdxV)
      .def_property_readonly("limit_idx_q", &WbcModel::limitIdxQ)
      .def_property_readonly("limit_idx_v", &WbcModel::limitIdxV)
      .def_property_readonly("limit_lower", &WbcModel::limitLower)
      .def_property_readonly("limit_upper", &WbcModel::limitUpper)
      .def_property_readonly("sole_frames", [](const WbcModel& w) {
        return std::array<std::size_t, kNumFeet>{w.soleFrame(kLeft), w.soleFrame(kRight)};
      })
      .def_property_readonly("torso_frame", &WbcModel::torsoFrame)
      .def_property_readonly("joint_names", &WbcModel::jointNames)
      .def_property_readonly("joint_idx_q", &WbcModel::jointIdxQ)
      .def_property_readonly("joint_idx_v", &WbcModel::jointIdxV)
      .def_property_readonly("joint_nq", &WbcModel::jointNq)
      .def_property_readonly("lower_position_limit", &WbcModel::lowerPositionLimit)
      .def_property_readonly("upper_position_limit", &WbcModel::upperPositionLimit)
      .def_property_readonly("neutral", &WbcModel::neutral)
      .def_property_readonly("base_quaternion_idx", &WbcModel::baseQuaternionIdx)
      .def_property_readonly("base_idx_v", &WbcModel::baseIdxV)
      .def_property_readonly("base_kind", &WbcModel::baseKind)
      .def_property_readonly("n_loop_rows", &WbcModel::nLoopRows)
      .def_property_readonly("n_constraint_rows", &WbcModel::nConstraintRows)
      .def_property_readonly("rigid_springs", &WbcModel::rigidSprings)
      .def_property_readonly("spring_idx_q", &WbcModel::springIdxQ)
      .def_property_readonly("spring_idx_v", &WbcModel::springIdxV)
      .def_property_readonly("eliminates_loops", &WbcModel::eliminatesLoops)
      .def_property_readonly("dependent_idx_v", &WbcModel::dependentIdxV)
      .def_property_readonly("independent_idx_v", &WbcModel::independentIdxV)
      .def_property_readonly(
          "loops",
          [](const WbcModel& w) {
            py::list out;
            for (const LoopClosure& c : w.loops()) {
              py::dict d;
              d["joint1"] = c.joint1;
              d["joint2"] = c.joint2;
              d["anchor1"] = c.anchor1;
              d["anchor2"] = c.anchor2;
              d["frame1"] = c.frame1;
              d["frame2"] = c.frame2;
              out.append(d);
            }
            return out;
          },
          "Loop closures: joint names and anchors [m] in the joint frames, one dict per loop.")
      .def_property_readonly(
          "qp_coordinates",
          [](const WbcModel& w) {
            const QpCoordinates& c = w.qpCoordinates();
            py::dict d;
            d["n"] = c.n;
            d["B"] = c.B;
            d["B_pinv"] = c.B_pinv;
            d["N_T"] = c.N_T;
            d["arm_idx"] = c.arm_idx;
            d["limit_idx"] = c.limit_idx;
            return d;
          },
          "The QP's acceleration coordinates: n, actuation B, B_pinv, unactuated rows N_T, arm_idx.");
}

}  // namespace lipmpcc::wbc::bindings
