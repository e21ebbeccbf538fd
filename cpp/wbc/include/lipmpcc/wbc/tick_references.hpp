// The full-body loop's per-tick references (the LIP COM reference, the swing-foot and torso-heading
// step trajectory, their rotations), the compiled twin of the Python reference:
//   lipmpcc.control.references.LipComReference.evaluate, StepTrajectory._full_lists (with
//   PhaseClock.tau / tau_dot, smoothstep5, apex_bump, Quintic._evaluate_lists), lipmpcc.rotations.yaw_rotation.
// Same operations in the same order on doubles, so the results are the Python ones to the bit:
// Python's `x ** n` is libm's pow(x, n), its max(a, b) / min(a, b) keep `a` unless `b` is larger /
// smaller, and numpy's small matmul (the correction quintic) accumulates with fused multiply-adds in
// k order on this machine's OpenBLAS (checked at first use by lipmpcc.control.tick_references; where it
// does not, the Python path is used). The file is compiled with -ffp-contract=off -fno-builtin.
// Units: time [s], lengths [m], angles [rad].
#pragma once

namespace lipmpcc::wbc::tickref {

// LIP segment: t0 [s], omega [1/s], com height [m], c0 (x, y) [m], v0 (x, y) [m/s], pivot (x, y) [m]
constexpr int kLipStateSize = 9;
// Step: phase (t_i [s], tau_i, t_end [s]); per coordinate of r = (x, y, z, foot yaw, torso yaw):
// (r_0, r_f - r_0, apex height); correction: present (1/0), t0, t1 [s], coefficients c (6 x 5, row-major)
constexpr int kStepStateSize = 3 + 15 + 3 + 30;

struct LipSample {
  double pos[3], vel[3], acc[3];  // [m], [m/s], [m/s^2]
};

struct StepSample {
  double tau;                     // step phase [-]
  double r[5], dr[5], ddr[5];     // r, its first and second time derivatives
};

// COM position, velocity, acceleration at t [s] (LipComReference.evaluate).
void lipEvaluate(const double* lip, double t, LipSample& out);

// Phase and r, r', r'' at t [s] (StepTrajectory.evaluate's numbers).
void stepEvaluate(const double* step, double t, StepSample& out);

// Row-major 3 x 3 rotation of a pure yaw [rad] about the world z axis (yaw_rotation).
void yawRotation(double yaw, double* rot9);

}  // namespace lipmpcc::wbc::tickref
