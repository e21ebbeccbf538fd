// Declarations shared by the pybind11 translation units of lipmpcc._wbc.
#pragma once

#include <pybind11/pybind11.h>

namespace lipmpcc::wbc::bindings {

void bindTypes(pybind11::module_& m);
void bindModel(pybind11::module_& m);
void bindSolver(pybind11::module_& m);
void bindTickReferences(pybind11::module_& m);

}  // namespace lipmpcc::wbc::bindings
