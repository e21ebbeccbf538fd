// lipmpcc._wbc: private pybind11 module of the C++ whole-body QP. Use lipmpcc.wbc instead.
#include "bindings.hpp"

PYBIND11_MODULE(_wbc, m) {
  m.doc() = "C++ whole-body QP (Pinocchio + proxsuite). Private: use lipmpcc.wbc.";
  lipmpcc::wbc::bindings::bindTypes(m);
  lipmpcc::wbc::bindings::bindModel(m);
  lipmpcc::wbc::bindings::bindSolver(m);
  lipmpcc::wbc::bindings::bindTickReferences(m);
}
