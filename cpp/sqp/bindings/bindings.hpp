// Declarations shared by the pybind11 translation units of lipmpcc._sqp.
#pragma once

#include <pybind11/pybind11.h>

namespace lipmpcc::sqp::bindings {

void bindCasadiFunction(pybind11::module_& m);
void bindCondensedSqp(pybind11::module_& m);
void bindLipRollout(pybind11::module_& m);

}  // namespace lipmpcc::sqp::bindings
