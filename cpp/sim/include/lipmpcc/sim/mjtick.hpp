// One control tick of lipmpcc.sim.RobotSim on raw MuJoCo pointers: the step (mj_step2 on a primed
// state, then mj_step, pushes through xfrc_applied) and the measurement that follows (the
// mj_forward-equivalent stages, subtree COM velocity, torso and sole frames, per-foot contact forces,
// the MuJoCo -> Pinocchio state map). Free of Python types; every operation reproduces the Python
// code of robot_sim.py bit for bit (same MuJoCo calls, same floating-point operations in the same
// order). Build with -ffp-contract=off.
#pragma once

#include <mujoco/mujoco.h>

#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace lipmpcc::sim {

struct TickConfig {
  int torso = -1;
  int sole_site[2] = {-1, -1};          // sites at the sole centres (both required)
  std::vector<int> geom_side;           // per geom: -1 none, 0 left foot, 1 right foot
  std::vector<std::uint8_t> geom_robot; // per geom: belongs to the robot
  std::vector<int> perm;                // q_pinocchio[i] = qpos[perm[i]]
  std::vector<std::pair<int, int>> free_quat;  // (index of x in Pinocchio's q, dof address)
  bool split = true;                    // mj_step = mj_step1 + mj_step2 (every integrator but RK4)
  bool fma_rotation = true;             // R^T v as numpy's BLAS does it (fused multiply-adds)
};

// Layout of the measurement buffer (doubles), see Tick::measure.
struct MeasureLayout {
  int time = 0, q, v, com, com_vel, torso_pos, torso_rot, foot_pos[2], foot_rot[2], force[2], other, peak[2], size;
  MeasureLayout(int nq, int nv);
};

class Tick {
 public:
  // m and d must outlive the Tick (the Python wrapper keeps the MjModel/MjData alive).
  Tick(const mjModel* m, mjData* d, TickConfig cfg);

  // RobotSim._ensure_forward on a stale state: mj_step1 + acceleration stages and a snapshot of
  // (qpos, qvel, act) (split integrators), else mj_forward.
  void prime();
  // RobotSim._take_primed: true (once) when the primed stages belong to the current state.
  bool take_primed();
  bool primed() const { return primed_; }

  // Pushes (RobotSim.add_push / reset): world force on `body` for t0 <= t < t1.
  void add_push(int body, const double f[3], double t0, double t1);
  void clear_pushes() { pushes_.clear(); }

  // Hold ctrl (nu) for n >= 1 steps (no log). Returns false, doing nothing, when ctrl is not finite.
  // After every substep it reads the feet's vertical contact forces of the state the substep started
  // from (its contacts) into the peaks (RobotSim._latch_contacts), except a state measure() has read.
  bool step(const double* ctrl, long n);

  // Forget the contact peaks (RobotSim.reset / set_state): the next measure() starts them afresh.
  void forget_contacts();

  // World contact force on each foot and whether another robot geom touches (RobotSim._foot_contacts).
  bool contacts(double fl[3], double fr[3]) const;

  // RobotSim.pinocchio_state into out's q and v slots (MeasureLayout), before any forward pass.
  // Returns 0, or 1 (non-finite state) / 2 (zero free-joint quaternion).
  int state(double* out);
  // Everything of RobotSim.measure into out (MeasureLayout), with the peaks: the largest vertical
  // force on each foot [N] over the states since the previous measure() (this one included); then
  // they restart. `stale`: run prime() first. `mapped`:
  // state(out) has returned 0 for the current state (it is not repeated). Returns 0, or state()'s
  // error, having changed nothing in the simulation.
  int measure(double* out, bool stale, bool mapped = false);

  // R(w, x, y, z)^T v as StateMap does it (for the import-time check of the rotation mode).
  static int rotate_transposed(double w, double x, double y, double z, const double v[3], double out[3],
                               bool fma_rotation);

  const MeasureLayout& layout() const { return layout_; }

 private:
  struct PushRec {
    int body;
    double f[3];
    double t0, t1;
  };
  void apply_pushes();
  void latch_contacts();

  const mjModel* m_;
  mjData* d_;
  TickConfig cfg_;
  MeasureLayout layout_;
  bool primed_ = false;
  std::vector<mjtNum> snap_;          // qpos, qvel, act at prime()
  std::vector<PushRec> pushes_;
  std::vector<int> pushed_bodies_;    // every body ever pushed (RobotSim keeps them across resets)
  double peak_[2] = {-HUGE_VAL, -HUGE_VAL};  // largest vertical foot force since the last measure() [N]
  bool measured_ = false;             // the current state's contacts are in a measurement (or peaks)
};

}  // namespace lipmpcc::sim
