// lipmpcc._wbc.tick_references: one call per WBC tick of the full-body loop that evaluates the LIP COM
// reference and (single support) the step trajectory and writes them into the flat reference buffer
// (lipmpcc.control.wbc_types.PackedWbcReference). Used by lipmpcc.control.tick_references.
#include <pybind11/numpy.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "bindings.hpp"
#include "lipmpcc/wbc/tick_references.hpp"

namespace py = pybind11;

namespace lipmpcc::wbc::bindings {
namespace {

using Arr = py::array_t<double, py::array::c_style>;

// A read-only pointer to `n` doubles of a C-contiguous float64 array named `name`.
const double* input(const Arr& a, py::ssize_t n, const char* name) {
  if (a.ndim() != 1 || a.shape(0) != n)
    throw std::invalid_argument(std::string(name) + ": expected " + std::to_string(n) + " float64 entries");
  return a.data();
}

// A writable pointer to at least `n` doubles of the caller's C-contiguous float64 buffer (never a copy).
double* output(py::array& a, py::ssize_t n, const char* name) {
  if (!py::isinstance<py::array_t<double>>(a) || !(a.flags() & py::array::c_style) || !a.writeable() ||
      a.size() < n)
    throw std::invalid_argument(std::string(name) + ": expected a writable C-contiguous float64 buffer of " +
                                std::to_string(n) + " entries or more");
  return static_cast<double*>(a.mutable_data());
}

py::array_t<double> vec3(const double* x) {
  py::array_t<double> a(3);
  double* p = a.mutable_data();
  p[0] = x[0];
  p[1] = x[1];
  p[2] = x[2];
  return a;
}

py::tuple tickReferences(double t, const Arr& lip, const py::object& step, int swing_index, double yaw_ref,
                         py::array& packed, py::array& feet) {
  const double* lip_state = input(lip, tickref::kLipStateSize, "lip");
  double* head = output(packed, 24, "packed");
  double* feet_block = output(feet, 48, "feet");
  tickref::LipSample com;
  tickref::lipEvaluate(lip_state, t, com);
  double yaw = yaw_ref, yaw_rate = 0.0, yaw_acc = 0.0;
  py::object swing_pos = py::none();
  double phase = std::nan("");
  if (!step.is_none()) {
    if (swing_index != 0 && swing_index != 1) throw std::invalid_argument("swing_index: expected 0 or 1");
    const Arr step_arr = step.cast<Arr>();
    tickref::StepSample s;
    tickref::stepEvaluate(input(step_arr, tickref::kStepStateSize, "step"), t, s);
    double* row = feet_block + 24 * swing_index;  // pos, vel, acc, rot (row-major), angvel, angacc
    for (int k = 0; k < 3; ++k) {
      row[k] = s.r[k];
      row[3 + k] = s.dr[k];
      row[6 + k] = s.ddr[k];
    }
    tickref::yawRotation(s.r[3], row + 9);
    row[20] = s.dr[3];  // the foot turns about the vertical only: x, y rates are never written
    row[23] = s.ddr[3];
    yaw = s.r[4];
    yaw_rate = s.dr[4];
    yaw_acc = s.ddr[4];
    swing_pos = vec3(s.r);
    phase = s.tau;
  }
  for (int k = 0; k < 3; ++k) {
    head[k] = com.pos[k];
    head[3 + k] = com.vel[k];
    head[6 + k] = com.acc[k];
  }
  tickref::yawRotation(yaw, head + 9);
  head[18] = head[19] = head[21] = head[22] = 0.0;
  head[20] = yaw_rate;
  head[23] = yaw_acc;
  return py::make_tuple(vec3(com.pos), swing_pos, phase, yaw);
}

}  // namespace

void bindTickReferences(py::module_& m) {
  m.attr("TICK_LIP_STATE_SIZE") = tickref::kLipStateSize;
  m.attr("TICK_STEP_STATE_SIZE") = tickref::kStepStateSize;
  m.def("tick_references", &tickReferences, py::arg("t"), py::arg("lip"), py::arg("step"), py::arg("swing_index"),
        py::arg("yaw_ref"), py::arg("packed"), py::arg("feet"),
        "One tick's COM (and, with a step state, swing-foot and torso-heading) references written into the flat "
        "reference `packed` (its first 24 entries) and `feet` (2 x 24); returns (com (3,) [m], swing_pos (3,) [m] "
        "or None, phase (NaN without a step), torso yaw [rad]). Bit-equal to the Python reference.");
}

}  // namespace lipmpcc::wbc::bindings
