// Binding of CondensedSqp, its settings, results and trace rows.
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "lipmpcc/sqp/condensed_sqp.hpp"

namespace py = pybind11;

namespace lipmpcc::sqp::bindings {

void bindCondensedSqp(py::module_& m) {
  py::enum_<Convexification>(m, "Convexification", "How the Hessian is made positive definite.")
      .value("EigenClip", Convexification::EigenClip)
      .value("ModifiedCholesky", Convexification::ModifiedCholesky);

  py::class_<SqpSettings>(m, "SqpSettings", "Options of CondensedSqp (the Python class's arguments).")
      .def(py::init<>())
      .def_readwrite("max_iter", &SqpSettings::max_iter)
      .def_readwrite("tol", &SqpSettings::tol)
      .def_readwrite("eig_floor", &SqpSettings::eig_floor)
      .def_readwrite("convexification", &SqpSettings::convexification)
      .def_readwrite("partial_eigen", &SqpSettings::partial_eigen)
      .def_readwrite("second_order_correction", &SqpSettings::second_order_correction)
      .def_readwrite("rate_stop", &SqpSettings::rate_stop)
      .def_readwrite("warm_start", &SqpSettings::warm_start);

  py::class_<SqpResult>(m, "SqpResult", "One solve: SqpSolution's fields, the next multipliers and counters.")
      .def_readonly("found", &SqpResult::found)
      .def_readonly("status", &SqpResult::status)
      .def_readonly("iterations", &SqpResult::iterations)
      .def_readonly("cost", &SqpResult::cost)
      .def_readonly("u", &SqpResult::u)
      .def_readonly("lam", &SqpResult::lam)
      .def_readonly("qp_time", &SqpResult::qp_time, "time in DAQP during this solve [s]")
      .def_readonly("qp_iters", &SqpResult::qp_iters)
      .def_property_readonly("trace", [](const SqpResult& r) {
        py::list rows;
        for (const TraceRow& t : r.trace) rows.append(py::make_tuple(t.iteration, t.alpha, t.max_du, t.qp_iterations));
        return rows;
      });

  py::class_<CondensedSqp>(m, "CondensedSqp", "The SQP of lipmpcc.solvers.condensed_sqp in C++ (private).")
      .def(py::init<std::shared_ptr<CasadiFunction>, std::shared_ptr<CasadiFunction>, const Vec&, const Vec&,
                    const Vec&, const Vec&, const SqpSettings&>(),
           py::arg("terms"), py::arg("merit"), py::arg("lbg"), py::arg("ubg"), py::arg("lbu"), py::arg("ubu"),
           py::arg("settings"))
      .def_property_readonly("nu", &CondensedSqp::nu)
      .def_property_readonly("m", &CondensedSqp::m)
      .def_property_readonly("n_params", &CondensedSqp::nParams)
      .def("param_size", &CondensedSqp::paramSize, py::arg("i"))
      .def("replace_functions", &CondensedSqp::replaceFunctions, py::arg("terms"), py::arg("merit"),
           "Evaluate with these functions from now on (None keeps one), the warm start kept.")
      .def("uses_callback", &CondensedSqp::usesCallback, py::arg("which"),
           "Whether the terms (0) or merit (1) function is a callback.")
      .def("solve", &CondensedSqp::solve, py::arg("u0"), py::arg("params"), py::arg("lam"),
           py::arg("record_trace") = false, py::call_guard<py::gil_scoped_release>());
}

}  // namespace lipmpcc::sqp::bindings
