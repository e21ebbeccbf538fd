// Binding of CasadiFunction (a CasADi-generated C function loaded from its shared library).
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "lipmpcc/sqp/casadi_function.hpp"

namespace py = pybind11;

namespace lipmpcc::sqp::bindings {

namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// Evaluates with one array per input (flattened, column-major for matrices); returns one flat
/// array per output (column-major).
py::list call(CasadiFunction& f, const std::vector<Array>& args) {
  if (static_cast<int>(args.size()) != f.nIn())
    throw py::value_error("CasadiFunction: expected " + std::to_string(f.nIn()) + " inputs, got " +
                          std::to_string(args.size()));
  std::vector<const double*> a;
  for (int i = 0; i < f.nIn(); ++i) {
    if (args[static_cast<std::size_t>(i)].size() != f.inSize(i))
      throw py::value_error("CasadiFunction: input " + std::to_string(i) + " must have " +
                            std::to_string(f.inSize(i)) + " values");
    a.push_back(args[static_cast<std::size_t>(i)].data());
  }
  std::vector<Array> out;
  std::vector<double*> r;
  for (int j = 0; j < f.nOut(); ++j) {
    out.emplace_back(f.outSize(j));
    r.push_back(out.back().mutable_data());
  }
  f.eval(a.data(), r.data());
  py::list res;
  for (auto& o : out) res.append(o);
  return res;
}

}  // namespace

void bindCasadiFunction(py::module_& m) {
  py::class_<CasadiFunction, std::shared_ptr<CasadiFunction>>(
      m, "CasadiFunction", "A CasADi-generated C function loaded from its shared library (dense inputs/outputs).")
      .def(py::init<const std::string&, const std::string&>(), py::arg("path"), py::arg("symbol"))
      .def_property_readonly("n_in", &CasadiFunction::nIn)
      .def_property_readonly("n_out", &CasadiFunction::nOut)
      .def("in_size", &CasadiFunction::inSize, py::arg("i"))
      .def("out_size", &CasadiFunction::outSize, py::arg("j"))
      .def_property_readonly("path", &CasadiFunction::path)
      .def_property_readonly("symbol", &CasadiFunction::symbol)
      .def("__call__", &call, py::arg("args"), "Evaluate: one flat array per input -> one flat array per output.");
}

}  // namespace lipmpcc::sqp::bindings
