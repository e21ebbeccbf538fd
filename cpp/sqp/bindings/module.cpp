// lipmpcc._sqp: private pybind11 module of the C++ condensed SQP. Use lipmpcc.solvers.condensed_sqp instead.
#include "bindings.hpp"

PYBIND11_MODULE(_sqp, m) {
  m.doc() = "C++ condensed SQP (Eigen + DAQP + CasADi-generated C). Private: use lipmpcc.solvers.condensed_sqp.";
  lipmpcc::sqp::bindings::bindCasadiFunction(m);
  lipmpcc::sqp::bindings::bindCondensedSqp(m);
  lipmpcc::sqp::bindings::bindLipRollout(m);
}
