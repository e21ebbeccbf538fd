#include "lipmpcc/sim/mjtick.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace lipmpcc::sim {

MeasureLayout::MeasureLayout(int nq, int nv) {
  int k = 1;
  q = k; k += nq;
  v = k; k += nv;
  com = k; k += 3;
  com_vel = k; k += 3;
  torso_pos = k; k += 3;
  torso_rot = k; k += 9;
  for (int s = 0; s < 2; ++s) { foot_pos[s] = k; k += 3; foot_rot[s] = k; k += 9; }
  for (int s = 0; s < 2; ++s) { force[s] = k; k += 3; }
  other = k; k += 1;
  for (int s = 0; s < 2; ++s) { peak[s] = k; k += 1; }
  size = k;
}

Tick::Tick(const mjModel* m, mjData* d, TickConfig cfg)
    : m_(m), d_(d), cfg_(std::move(cfg)), layout_(m->nq, m->nv),
      snap_(static_cast<size_t>(m->nq + m->nv + m->na)) {}

void Tick::prime() {
  const mjModel* m = m_;
  mjData* d = d_;
  if (cfg_.split) {
    mj_step1(m, d);
    mj_fwdActuation(m, d);
    mj_fwdAcceleration(m, d);
    mj_fwdConstraint(m, d);
    mj_sensorAcc(m, d);
    mjtNum* s = snap_.data();
    std::memcpy(s, d->qpos, sizeof(mjtNum) * m->nq);
    std::memcpy(s + m->nq, d->qvel, sizeof(mjtNum) * m->nv);
    std::memcpy(s + m->nq + m->nv, d->act, sizeof(mjtNum) * m->na);
    primed_ = true;
  } else {
    mj_forward(m, d);
  }
}

bool Tick::take_primed() {
  if (!primed_) return false;
  primed_ = false;
  const mjModel* m = m_;
  const mjtNum* s = snap_.data();
  // a byte comparison, as Python's bytes equality (a hand edit to -0.0 or a NaN payload counts)
  return std::memcmp(s, d_->qpos, sizeof(mjtNum) * m->nq) == 0 &&
         std::memcmp(s + m->nq, d_->qvel, sizeof(mjtNum) * m->nv) == 0 &&
         std::memcmp(s + m->nq + m->nv, d_->act, sizeof(mjtNum) * m->na) == 0;
}

void Tick::add_push(int body, const double f[3], double t0, double t1) {
  pushes_.push_back(PushRec{body, {f[0], f[1], f[2]}, t0, t1});
  if (std::find(pushed_bodies_.begin(), pushed_bodies_.end(), body) == pushed_bodies_.end())
    pushed_bodies_.push_back(body);
}

void Tick::apply_pushes() {
  const mjtNum t = d_->time;
  mjtNum* xfrc = d_->xfrc_applied;
  for (int b : pushed_bodies_) xfrc[6 * b] = xfrc[6 * b + 1] = xfrc[6 * b + 2] = 0.0;
  for (const PushRec& p : pushes_) {
    if (p.t0 <= t && t < p.t1) {
      mjtNum* x = xfrc + 6 * p.body;
      x[0] += p.f[0];
      x[1] += p.f[1];
      x[2] += p.f[2];
    }
  }
}

bool Tick::step(const double* ctrl, long n) {
  const mjModel* m = m_;
  mjData* d = d_;
  for (int i = 0; i < m->nu; ++i)
    if (!std::isfinite(ctrl[i])) return false;
  std::memcpy(d->ctrl, ctrl, sizeof(mjtNum) * m->nu);
  const bool pushes = !pushes_.empty();
  long left = n;
  // Applying the pushes before every substep gives the same xfrc_applied as RobotSim's runs of
  // steps with unchanged active pushes (zeroed, then summed in push order, at the step's start time).
  // After each substep, d's contacts are those of the state it started from: the first one's were
  // measured when measured_ is set, the others are new (RobotSim.step does the same).
  bool seen = measured_;
  if (take_primed()) {
    if (pushes) apply_pushes();
    mj_step2(m, d);
    if (!seen) latch_contacts();
    seen = false;
    --left;
  }
  for (; left > 0; --left) {
    if (pushes) apply_pushes();
    mj_step(m, d);
    if (!seen) latch_contacts();
    seen = false;
  }
  measured_ = false;
  return true;
}

void Tick::latch_contacts() {
  double fl[3], fr[3];
  contacts(fl, fr);
  peak_[0] = std::max(peak_[0], fl[2]);
  peak_[1] = std::max(peak_[1], fr[2]);
}

void Tick::forget_contacts() {
  peak_[0] = peak_[1] = -HUGE_VAL;
  measured_ = false;
}

bool Tick::contacts(double fl[3], double fr[3]) const {
  const mjModel* m = m_;
  const mjData* d = d_;
  fl[0] = fl[1] = fl[2] = 0.0;
  fr[0] = fr[1] = fr[2] = 0.0;
  bool other = false;
  const int ng = m->ngeom;
  // Python indexing: a flex contact's geom id -1 reads the last geom's entry
  auto side = [&](int g) { return cfg_.geom_side[g >= 0 ? g : ng + g]; };
  auto robot = [&](int g) { return cfg_.geom_robot[g >= 0 ? g : ng + g] != 0; };
  mjtNum f6[6];
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    const int g1 = c.geom[0], g2 = c.geom[1];
    const int s1 = side(g1), s2 = side(g2);
    if (s1 < 0 && s2 < 0) {
      other = other || robot(g1) || robot(g2);
      continue;
    }
    mj_contactForce(m, d, i, f6);  // contact frame: normal, tangent 1, tangent 2
    const double fn = f6[0], t1 = f6[1], t2 = f6[2];
    const mjtNum* a = c.frame;  // rows: the contact frame's axes in the world
    const double x = a[0] * fn + a[3] * t1 + a[6] * t2;
    const double y = a[1] * fn + a[4] * t1 + a[7] * t2;
    const double z = a[2] * fn + a[5] * t1 + a[8] * t2;
    if (s2 >= 0) {  // the force of geom1 on geom2
      double* acc = s2 ? fr : fl;
      acc[0] += x;
      acc[1] += y;
      acc[2] += z;
    }
    if (s1 >= 0) {
      double* acc = s1 ? fr : fl;
      acc[0] -= x;
      acc[1] -= y;
      acc[2] -= z;
    }
  }
  return other;
}

int Tick::rotate_transposed(double qw, double qx, double qy, double qz, const double v[3], double out[3],
                            bool fma_rotation) {
  // lipmpcc.sim.robot_sim._quat_wxyz_to_rot, then numpy's R.T @ v
  const double n = std::sqrt(qw * qw + qx * qx + qy * qy + qz * qz);
  if (!(n > 0.0)) return 2;
  qw = qw / n; qx = qx / n; qy = qy / n; qz = qz / n;
  const double R[9] = {
      1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw),
      2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw),
      2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy),
  };
  for (int i = 0; i < 3; ++i) {
    if (fma_rotation)  // OpenBLAS dgemv_t (Haswell and later kernels)
      out[i] = std::fma(R[6 + i], v[2], std::fma(R[3 + i], v[1], R[i] * v[0]));
    else
      out[i] = R[i] * v[0] + R[3 + i] * v[1] + R[6 + i] * v[2];
  }
  return 0;
}

int Tick::state(double* out) {
  const mjModel* m = m_;
  mjData* d = d_;
  const MeasureLayout& L = layout_;
  // RobotSim.pinocchio_state: finite check, then the map (before any forward pass)
  for (int i = 0; i < m->nq; ++i)
    if (!std::isfinite(d->qpos[i])) return 1;
  for (int i = 0; i < m->nv; ++i)
    if (!std::isfinite(d->qvel[i])) return 1;
  double* q = out + L.q;
  double* v = out + L.v;
  const int* perm = cfg_.perm.data();
  for (int i = 0; i < m->nq; ++i) q[i] = d->qpos[perm[i]];
  std::memcpy(v, d->qvel, sizeof(double) * m->nv);
  for (const auto& [a, b] : cfg_.free_quat) {
    double r[3];
    if (rotate_transposed(q[a + 3], q[a], q[a + 1], q[a + 2], v + b, r, cfg_.fma_rotation)) return 2;
    v[b] = r[0];
    v[b + 1] = r[1];
    v[b + 2] = r[2];
  }
  return 0;
}

int Tick::measure(double* out, bool stale, bool mapped) {
  const mjModel* m = m_;
  mjData* d = d_;
  const MeasureLayout& L = layout_;
  if (!mapped) {
    const int status = state(out);
    if (status != 0) return status;
  }
  if (stale) prime();
  mj_subtreeVel(m, d);
  out[L.time] = d->time;
  const int t = cfg_.torso;
  std::memcpy(out + L.com, d->subtree_com + 3 * t, 3 * sizeof(double));
  std::memcpy(out + L.com_vel, d->subtree_linvel + 3 * t, 3 * sizeof(double));
  std::memcpy(out + L.torso_pos, d->xpos + 3 * t, 3 * sizeof(double));
  std::memcpy(out + L.torso_rot, d->xmat + 9 * t, 9 * sizeof(double));
  for (int s = 0; s < 2; ++s) {
    const int site = cfg_.sole_site[s];
    std::memcpy(out + L.foot_pos[s], d->site_xpos + 3 * site, 3 * sizeof(double));
    std::memcpy(out + L.foot_rot[s], d->site_xmat + 9 * site, 9 * sizeof(double));
  }
  const bool other = contacts(out + L.force[0], out + L.force[1]);
  out[L.other] = other ? 1.0 : 0.0;
  for (int s = 0; s < 2; ++s) {
    out[L.peak[s]] = std::max(peak_[s], out[L.force[s] + 2]);
    peak_[s] = -HUGE_VAL;
  }
  measured_ = true;
  return 0;
}

}  // namespace lipmpcc::sim
