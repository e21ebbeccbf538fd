// lipmpcc._mjtick: private pybind11 module of one RobotSim control tick on raw MuJoCo pointers
// (MjModel._address / MjData._address, as mujoco's own _rollout). Use lipmpcc.sim.RobotSim.
// The Python wrapper keeps the MjModel/MjData alive, validates arguments first, and compares
// mujoco_version() with the running mujoco before using it.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <string>

#include "lipmpcc/sim/mjtick.hpp"

namespace py = pybind11;
using lipmpcc::sim::Tick;
using lipmpcc::sim::TickConfig;
using Vec = py::array_t<double, py::array::c_style | py::array::forcecast>;

namespace {

void require(bool ok, const std::string& name, const std::string& expected) {
  if (!ok) throw py::value_error(name + ": expected " + expected);
}

class PyTick {
 public:
  PyTick(std::uintptr_t model, std::uintptr_t data, TickConfig cfg, py::array buffer)
      : m_(reinterpret_cast<const mjModel*>(model)),
        tick_(m_, reinterpret_cast<mjData*>(data), std::move(cfg)),
        buffer_(std::move(buffer)) {
    require(buffer_.dtype().is(py::dtype::of<double>()) && buffer_.ndim() == 1 &&
                buffer_.shape(0) == tick_.layout().size && (buffer_.flags() & py::array::c_style) &&
                buffer_.writeable(),
            "buffer", "a writeable contiguous float64 vector of size " + std::to_string(tick_.layout().size));
    out_ = static_cast<double*>(buffer_.mutable_data());
  }

  bool step(const Vec& ctrl, long n) {
    require(ctrl.ndim() == 1 && ctrl.shape(0) == m_->nu, "ctrl", "a float64 vector of shape (" +
            std::to_string(m_->nu) + ",)");
    require(n >= 1, "n", "a positive number of steps");
    py::gil_scoped_release release;  // as mujoco's own bindings around mj_step
    return tick_.step(ctrl.data(), n);
  }

  int state() { return tick_.state(out_); }
  int measure(bool stale, bool mapped) { return tick_.measure(out_, stale, mapped); }

  bool contacts() {  // into the buffer's force and other slots
    const auto& L = tick_.layout();
    double* out = out_;
    const bool other = tick_.contacts(out + L.force[0], out + L.force[1]);
    out[L.other] = other ? 1.0 : 0.0;
    return other;
  }

  void add_push(int body, double fx, double fy, double fz, double t0, double t1) {
    require(body >= 0 && body < m_->nbody, "body", "a body id of the model");
    const double f[3] = {fx, fy, fz};
    tick_.add_push(body, f, t0, t1);
  }

  Tick& tick() { return tick_; }

 private:
  const mjModel* m_;
  Tick tick_;
  py::array buffer_;  // owned by the Python wrapper; the reference keeps it alive
  double* out_;
};

py::dict layout_dict(int nq, int nv) {
  lipmpcc::sim::MeasureLayout L(nq, nv);
  py::dict out;
  out["time"] = L.time;
  out["q"] = L.q;
  out["v"] = L.v;
  out["com"] = L.com;
  out["com_vel"] = L.com_vel;
  out["torso_pos"] = L.torso_pos;
  out["torso_rot"] = L.torso_rot;
  out["foot_pos"] = py::make_tuple(L.foot_pos[0], L.foot_pos[1]);
  out["foot_rot"] = py::make_tuple(L.foot_rot[0], L.foot_rot[1]);
  out["force"] = py::make_tuple(L.force[0], L.force[1]);
  out["other"] = L.other;
  out["peak"] = py::make_tuple(L.peak[0], L.peak[1]);
  out["size"] = L.size;
  return out;
}

}  // namespace

PYBIND11_MODULE(_mjtick, mod) {
  mod.doc() = "One RobotSim control tick in C++ (MuJoCo). Private: use lipmpcc.sim.RobotSim.";
  mod.attr("mujoco_version") = py::int_(mjVERSION_HEADER);  // the headers compiled against
  mod.def("linked_mujoco_version", []() { return mj_version(); },
          "mj_version() of the libmujoco this module is linked to.");
  mod.def("layout", &layout_dict, py::arg("nq"), py::arg("nv"), "Offsets of the measurement buffer.");
  mod.def(
      "rotate_transposed",
      [](double w, double x, double y, double z, const Vec& v, bool fma_rotation) {
        require(v.ndim() == 1 && v.shape(0) == 3, "v", "a float64 vector of shape (3,)");
        py::array_t<double> out(3);
        int code = Tick::rotate_transposed(w, x, y, z, v.data(), out.mutable_data(), fma_rotation);
        require(code == 0, "quaternion", "a non-zero quaternion");
        return out;
      },
      py::arg("w"), py::arg("x"), py::arg("y"), py::arg("z"), py::arg("v"), py::arg("fma_rotation"));

  py::class_<TickConfig>(mod, "TickConfig")
      .def(py::init<>())
      .def_readwrite("torso", &TickConfig::torso)
      .def_property(
          "sole_site", [](const TickConfig& c) { return py::make_tuple(c.sole_site[0], c.sole_site[1]); },
          [](TickConfig& c, std::pair<int, int> s) { c.sole_site[0] = s.first; c.sole_site[1] = s.second; })
      .def_readwrite("geom_side", &TickConfig::geom_side)
      .def_readwrite("geom_robot", &TickConfig::geom_robot)
      .def_readwrite("perm", &TickConfig::perm)
      .def_readwrite("free_quat", &TickConfig::free_quat)
      .def_readwrite("split", &TickConfig::split)
      .def_readwrite("fma_rotation", &TickConfig::fma_rotation);

  py::class_<PyTick>(mod, "Tick")
      .def(py::init([](std::uintptr_t model, std::uintptr_t data, TickConfig cfg, py::array buffer) {
             const auto* m = reinterpret_cast<const mjModel*>(model);
             require(model != 0 && data != 0, "model/data", "MjModel._address and MjData._address");
             require(cfg.torso >= 0 && cfg.torso < m->nbody, "torso", "a body id");
             for (int s : cfg.sole_site) require(s >= 0 && s < m->nsite, "sole_site", "two site ids");
             require(static_cast<int>(cfg.geom_side.size()) == m->ngeom &&
                         static_cast<int>(cfg.geom_robot.size()) == m->ngeom,
                     "geom_side/geom_robot", "one entry per geom");
             require(static_cast<int>(cfg.perm.size()) == m->nq, "perm", "one entry per qpos");
             for (int p : cfg.perm) require(p >= 0 && p < m->nq, "perm", "qpos indices");
             for (auto [a, b] : cfg.free_quat)
               require(a >= 0 && a + 4 <= m->nq && b >= 0 && b + 3 <= m->nv, "free_quat", "(q, dof) addresses");
             return new PyTick(model, data, std::move(cfg), std::move(buffer));
           }),
           py::arg("model"), py::arg("data"), py::arg("config"), py::arg("buffer"), py::keep_alive<1, 5>())
      .def("prime", [](PyTick& t) { t.tick().prime(); })
      .def("take_primed", [](PyTick& t) { return t.tick().take_primed(); })
      .def_property_readonly("primed", [](PyTick& t) { return t.tick().primed(); })
      .def("add_push", &PyTick::add_push, py::arg("body"), py::arg("fx"), py::arg("fy"), py::arg("fz"),
           py::arg("t_start"), py::arg("t_end"))
      .def("clear_pushes", [](PyTick& t) { t.tick().clear_pushes(); })
      .def("forget_contacts", [](PyTick& t) { t.tick().forget_contacts(); },
           "Forget the contact peaks (a reset or a new state).")
      .def("step", &PyTick::step, py::arg("ctrl"), py::arg("n"),
           "Hold ctrl for n steps; False (nothing done) when ctrl is not finite.")
      .def("state", &PyTick::state,
           "Pinocchio q and v into the buffer: 0, or 1 non-finite state / 2 zero quaternion.")
      .def("measure", &PyTick::measure, py::arg("stale"), py::arg("mapped") = false,
           "Measurement into the buffer (mapped: state() returned 0 for this state): 0, or 1 "
           "non-finite state / 2 zero quaternion (nothing done).")
      .def("contacts", &PyTick::contacts, "Per-foot contact forces into the buffer; True on a non-foot contact.");
}
