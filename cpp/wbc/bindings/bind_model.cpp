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
      .def_property_readonly("arm_idx_q", &WbcModel::armIdxQ)
      .def_property_readonly("arm_idx_v", &WbcModel::armIdxV)
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
      .def_property_readonly("neutral", &WbcModel::neutral);
}

}  // namespace lipmpcc::wbc::bindings
