// Binding of lipRollout (the fixed-T MPCC's roll-out, bit-equal to lipmpcc.planners.mpcc's Python reference).
#include <pybind11/numpy.h>

#include <string>

#include "bindings.hpp"
#include "lipmpcc/sqp/lip_rollout.hpp"

namespace py = pybind11;

namespace lipmpcc::sqp::bindings {

namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

py::array_t<double> rollout(const Array& x0, const Array& u, double a01, double a11, double b0, double b1,
                            double theta_max) {
  if (x0.size() != 6) throw py::value_error("lip_rollout: x0 must have 6 values, got " + std::to_string(x0.size()));
  if (u.ndim() != 2 || u.shape(1) < 4)
    throw py::value_error("lip_rollout: U must be an (N, k >= 4) array of stage inputs");
  const auto n = static_cast<int>(u.shape(0));
  py::array_t<double> out({static_cast<py::ssize_t>(n) + 1, static_cast<py::ssize_t>(6)});
  lipRollout(x0.data(), u.data(), n, static_cast<int>(u.shape(1)), a01, a11, b0, b1, theta_max, out.mutable_data());
  return out;
}

py::array_t<double> timedRollout(const Array& x_first, const Array& z, int n_head, int n_var, int n_stages, double w,
                                 double t_min, double gain, double theta_max) {
  if (x_first.size() != 6)
    throw py::value_error("timed_lip_rollout: x_first must have 6 values, got " + std::to_string(x_first.size()));
  if (n_head < 0 || n_var < 5 || n_stages < 0 || z.size() < static_cast<py::ssize_t>(n_head) + static_cast<py::ssize_t>(n_var) * n_stages)
    throw py::value_error("timed_lip_rollout: z must hold n_head + n_var * n_stages values (n_var >= 5)");
  py::array_t<double> out({static_cast<py::ssize_t>(n_stages) + 1, static_cast<py::ssize_t>(6)});
  timedLipRollout(x_first.data(), z.data(), n_head, n_var, n_stages, w, t_min, gain, theta_max, out.mutable_data());
  return out;
}

}  // namespace

void bindLipRollout(py::module_& m) {
  m.def("timed_lip_rollout", &timedRollout, py::arg("x_first"), py::arg("z"), py::arg("n_head"), py::arg("n_var"),
        py::arg("n_stages"), py::arg("w"), py::arg("t_min"), py::arg("gain"), py::arg("theta_max"),
        "Stage states (N+1, 6) of the timed MPCC's variables z from its first state: "
        "lipmpcc.planners.mpcc_timed's roll-out, bit for bit.");
  m.def("lip_rollout", &rollout, py::arg("x0"), py::arg("U"), py::arg("a01"), py::arg("a11"), py::arg("b0"),
        py::arg("b1"), py::arg("theta_max"),
        "Stage states (N+1, 6) of the 3D-LIP and ϑ from x0 (6,) and U (N, >= 4): lipmpcc.planners.mpcc.rollout's "
        "numbers, bit for bit.");
}

}  // namespace lipmpcc::sqp::bindings
