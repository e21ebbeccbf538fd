// Binding of WbcSolver (mutable workspace; one control tick per solve call).
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "lipmpcc/wbc/solver.hpp"

namespace py = pybind11;

namespace lipmpcc::wbc::bindings {

namespace {

py::dict termsDict(const DynamicsTerms& t) {
  py::dict d;
  d["M"] = t.M;
  d["h"] = t.h;
  d["J_sole"] = t.J_sole;
  d["drift_sole"] = t.drift_sole;
  d["p_sole"] = t.p_sole;
  d["R_sole"] = t.R_sole;
  d["com"] = t.com;
  d["vcom"] = t.vcom;
  d["J_com"] = t.J_com;
  d["drift_com"] = t.drift_com;
  d["R_torso"] = t.R_torso;
  d["J_torso"] = t.J_torso;
  d["drift_torso"] = t.drift_torso;
  d["A_ang"] = t.A_ang;
  d["drift_k"] = t.drift_k;
  d["vel_sole"] = t.vel_sole;
  d["w_torso"] = t.w_torso;
  d["k_com"] = t.k_com;
  d["J_loop"] = t.J_loop;
  d["gamma_loop"] = t.gamma_loop;
  d["loop_residual"] = t.loop_residual;
  d["qdd_metric"] = t.qdd_metric;
  d["qdd_metric_g"] = t.qdd_metric_g;
  return d;
}

// ---- packed fast path (used by lipmpcc/wbc.py: one array in, one array out per tick) ----------
// Reference: com_pos, com_vel, com_acc (3 each), torso_rot (9, row-major), torso_angvel,
// torso_angacc (3 each); per foot (left, right): pos, vel, acc (3 each), rot (9, row-major),
// angvel, angacc (3 each); max_normal_force (2); arm_posture (n_arm).
constexpr Eigen::Index kRefFixedSize = 24 + 2 * 24 + 2;
// Output: tau (nu), tau_joint (nv), qdd (nv), wrenches (2 x 6, row per foot), errors: com_pos,
// com_vel, torso_rot, torso_angvel (3 each), foot_pos (2 x 3), foot_rot (2 x 3), angular_momentum
// (3), arm_posture (n_arm); loop_forces (3 per loop); spring_torques (one per spring joint).
constexpr Eigen::Index kOutFixedSize = 12 + 12 + 12 + 3;

using RowMat3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

void unpackReference(const Eigen::Ref<const Vec>& p, WbcReference& r) {
  const double* x = p.data();
  auto v3 = [&x]() { Vec3 a(x[0], x[1], x[2]); x += 3; return a; };
  auto m3 = [&x]() { Mat3 a = Eigen::Map<const RowMat3>(x); x += 9; return a; };
  r.com_pos = v3();
  r.com_vel = v3();
  r.com_acc = v3();
  r.torso_rot = m3();
  r.torso_angvel = v3();
  r.torso_angacc = v3();
  for (std::size_t f = 0; f < kNumFeet; ++f) {
    r.foot_pos[f] = v3();
    r.foot_vel[f] = v3();
    r.foot_acc[f] = v3();
    r.foot_rot[f] = m3();
    r.foot_angvel[f] = v3();
    r.foot_angacc[f] = v3();
  }
  r.max_normal_force = {x[0], x[1]};
  x += 2;
  r.arm_posture = Eigen::Map<const Vec>(x, p.size() - kRefFixedSize);
}

Vec packOutput(const WbcOutput& o) {
  const Eigen::Index nu = o.tau.size(), nv = o.qdd.size(), na = o.errors.arm_posture.size();
  Vec out(nu + 2 * nv + kOutFixedSize + na + o.loop_forces.size() + o.spring_torques.size());
  Eigen::Index i = 0;
  auto put = [&out, &i](const auto& a) {
    out.segment(i, a.size()) = Eigen::Map<const Vec>(a.data(), a.size());
    i += a.size();
  };
  put(o.tau);
  put(o.tau_joint);
  put(o.qdd);
  for (int f = 0; f < kNumFeet; ++f) put(Vec6(o.wrenches.col(f)));
  const TaskErrors& e = o.errors;
  put(e.com_pos);
  put(e.com_vel);
  put(e.torso_rot);
  put(e.torso_angvel);
  for (std::size_t f = 0; f < kNumFeet; ++f) put(e.foot_pos[f]);
  for (std::size_t f = 0; f < kNumFeet; ++f) put(e.foot_rot[f]);
  put(e.angular_momentum);
  put(e.arm_posture);
  put(o.loop_forces);
  put(o.spring_torques);
  return out;
}

}  // namespace

void bindSolver(py::module_& m) {
  using RefV = Eigen::Ref<const Vec>;
  m.attr("PACKED_REFERENCE_FIXED_SIZE") = kRefFixedSize;
  m.attr("PACKED_OUTPUT_FIXED_SIZE") = kOutFixedSize;
  py::class_<WbcSolver>(m, "WbcSolver")
      .def(py::init<const WbcModel&, const WbcParams&>(), py::arg("model"), py::arg("params"))
      .def(
          "solve",
          [](WbcSolver& s, const RefV& q, const RefV& v, const WbcReference& ref) {
            WbcOutput out;
            {
              py::gil_scoped_release release;
              s.solveInto(q, v, ref, out);
            }
            return out;
          },
          py::arg("q"), py::arg("v"), py::arg("ref"))
      .def(
          "solve_packed",
          [](WbcSolver& s, const RefV& q, const RefV& v, bool contact_left, bool contact_right,
             const RefV& packed_ref) {
            const Eigen::Index n_arm = s.model().nArm();
            if (packed_ref.size() != kRefFixedSize + n_arm)
              throw std::invalid_argument("packed reference: expected " +
                                          std::to_string(kRefFixedSize + n_arm) + " entries");
            WbcOutput out;
            {
              py::gil_scoped_release release;
              WbcReference ref;
              ref.contact = {contact_left, contact_right};
              unpackReference(packed_ref, ref);
              s.solveInto(q, v, ref, out);
              if (out.errors.arm_posture.size() != n_arm) out.errors.arm_posture = Vec::Zero(n_arm);
              if (out.loop_forces.size() != s.model().nLoopRows())
                out.loop_forces = Vec::Zero(s.model().nLoopRows());
              const auto n_springs = static_cast<Eigen::Index>(s.model().springIdxQ().size());
              if (out.spring_torques.size() != n_springs) out.spring_torques = Vec::Zero(n_springs);
            }
            return py::make_tuple(packOutput(out), static_cast<int>(out.status), out.iterations,
                                  out.solve_time_us, out.tick_time_us, out.used_fallback);
          },
          py::arg("q"), py::arg("v"), py::arg("contact_left"), py::arg("contact_right"),
          py::arg("packed_ref"),
          "Fast path: the reference and the output as flat arrays (layout in bind_solver.cpp).")
      .def(
          "prepare",
          [](WbcSolver& s, const RefV& q, const RefV& v, bool async) {
            py::gil_scoped_release release;
            s.prepare(q, v, async);
          },
          py::arg("q"), py::arg("v"), py::arg("async_"),
          "Start the dynamics terms of (q, v) (on a worker thread with async_); a solve with equal q "
          "and v uses them.")
      .def("reset", &WbcSolver::reset)
      .def_property_readonly("qp_failures", &WbcSolver::qpFailures)
      .def_property_readonly("model", &WbcSolver::model)
      .def_property_readonly("params", &WbcSolver::params)
      .def_property_readonly("last_efforts", &WbcSolver::lastEfforts)
      .def("last_qp",
           [](const WbcSolver& s) {
             const QpProblem& p = s.lastProblem();
             py::dict d;
             d["H"] = p.H;
             d["g"] = p.g;
             d["A"] = p.A;
             d["b"] = p.b;
             d["C"] = p.C;
             d["l"] = p.l;
             d["u"] = p.u;
             d["n_var"] = p.layout.n_var;
             d["n_eq"] = p.layout.n_eq;
             d["n_in"] = p.layout.n_in;
             d["n_limits"] = p.layout.n_limits;
             d["wrench_offset"] = p.layout.wrench_offset;
             d["n_extra"] = p.layout.n_extra;
             d["extra_offset"] = p.layout.extra_offset;
             d["n_acc"] = p.layout.nv;
             return d;
           },
           "The QP matrices of the last tick (proxsuite form: 0.5 x'Hx + g'x, Ax = b, l <= Cx <= u).")
      .def("last_terms", [](const WbcSolver& s) { return termsDict(s.lastTerms()); },
           "Dynamics terms of the last tick.")
      .def("last_reduced_terms", [](const WbcSolver& s) { return termsDict(s.lastReducedTerms()); },
           "Terms in the independent accelerations the last QP was built from (eliminated loops).")
      .def(
          "evaluate",
          [](WbcSolver& s, const RefV& q, const RefV& v) { return termsDict(s.evaluate(q, v)); },
          py::arg("q"), py::arg("v"), "Dynamics terms at (q, v), without solving.");
}

}  // namespace lipmpcc::wbc::bindings
