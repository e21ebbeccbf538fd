"""Numerical solvers the planners build on, apart from any one planner's problem.

- :mod:`lipmpcc.solvers.condensed_sqp`: an SQP for condensed NLPs (the MPCC of paper A runs on it);
- :mod:`lipmpcc.solvers.sqp_compiled`: its C++ backend (``lipmpcc._sqp``) behind a validating wrapper;
- :mod:`lipmpcc.solvers.casadi_buffer`: fast repeated evaluation (and JIT compilation) of CasADi functions;
- :mod:`lipmpcc.solvers.blas_threads`: one OpenBLAS thread for small dense algebra.
"""

__all__ = ["condensed_sqp", "sqp_compiled", "casadi_buffer", "blas_threads"]
