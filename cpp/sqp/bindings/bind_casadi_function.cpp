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

/// A callback for CasadiFunction that calls ``fn(args, res)`` in Python (the GIL taken): ``args`` read-only
/// and ``res`` writable float64 views of the C++ arrays (no copies; valid during the call only).
CasadiFunction::Callback pythonCallback(py::function fn, std::vector<int> in_sizes, std::vector<int> out_sizes) {
  // the Python function is released with the GIL held, whichever thread drops the last reference
  std::shared_ptr<py::function> holder(new py::function(std::move(fn)), [](py::function* f) {
    py::gil_scoped_acquire gil;
    delete f;
  });
  return [holder, in_sizes, out_sizes](const double* const* args, double* const* res) {
    py::gil_scoped_acquire gil;
    py::capsule none(args, [](void*) {});  // a base object: the arrays view the C++ memory, never own it
    py::list a, r;
    for (std::size_t i = 0; i < in_sizes.size(); ++i) {
      py::array_t<double> v({static_cast<py::ssize_t>(in_sizes[i])}, {static_cast<py::ssize_t>(sizeof(double))},
                            args[i], none);
      py::detail::array_proxy(v.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
      a.append(v);
    }
    for (std::size_t j = 0; j < out_sizes.size(); ++j) {
      if (res[j] == nullptr) {
        r.append(py::none());
        continue;
      }
      r.append(py::array_t<double>({static_cast<py::ssize_t>(out_sizes[j])}, {static_cast<py::ssize_t>(sizeof(double))},
                                   res[j], none));
    }
    (*holder)(a, r);
  };
}

std::shared_ptr<CasadiFunction> fromCallback(py::function fn, std::vector<int> in_sizes,
                                             std::vector<std::pair<int, int>> out_shapes, const std::string& name) {
  std::vector<int> out_sizes;
  for (const auto& s : out_shapes) out_sizes.push_back(s.first * s.second);
  auto cb = pythonCallback(std::move(fn), in_sizes, out_sizes);
  return std::make_shared<CasadiFunction>(std::move(in_sizes), std::move(out_shapes), std::move(cb), name);
}

}  // namespace

void bindCasadiFunction(py::module_& m) {
  py::class_<CasadiFunction, std::shared_ptr<CasadiFunction>>(
      m, "CasadiFunction", "A CasADi-generated C function loaded from its shared library (dense inputs/outputs).")
      .def(py::init<const std::string&, const std::string&>(), py::arg("path"), py::arg("symbol"))
      .def(py::init(&fromCallback), py::arg("callback"), py::arg("in_sizes"), py::arg("out_shapes"), py::arg("name"),
           "The function evaluated by callback(args, res) in Python: args and res are lists of flat float64 views "
           "(column-major) of in_sizes / out_shapes doubles; res to be filled (an interpreted CasADi function).")
      .def_property_readonly("is_callback", &CasadiFunction::isCallback)
      .def_property_readonly("n_in", &CasadiFunction::nIn)
      .def_property_readonly("n_out", &CasadiFunction::nOut)
      .def("in_size", &CasadiFunction::inSize, py::arg("i"))
      .def("out_size", &CasadiFunction::outSize, py::arg("j"))
      .def_property_readonly("path", &CasadiFunction::path)
      .def_property_readonly("symbol", &CasadiFunction::symbol)
      .def("__call__", &call, py::arg("args"), "Evaluate: one flat array per input -> one flat array per output.");
}

}  // namespace lipmpcc::sqp::bindings
