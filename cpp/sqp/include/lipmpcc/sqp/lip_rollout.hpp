// The fixed-T MPCC's roll-out of the 3D-LIP and the path parameter (lipmpcc.planners.mpcc.rollout), the same
// floating-point operations in the same order as the Python reference (plain doubles; the file is compiled with
// -ffp-contract=off so that no product is fused into an addition): bit-equal results.
#pragma once

namespace lipmpcc::sqp {

/// Stage states out[(N+1) × 6] (row-major) = [x, ẋ, y, ẏ, heading, ϑ] from x0 (6) and the stage inputs
/// u[k * u_stride + 0..3] = [uˣ, uʸ, u^θ, v] (k = 0..N-1): x_{k+1} = A x_k + B u_k with A's and B's non-zero
/// entries (a01, a11; b0, b1), ϑ_{k+1} = min(ϑ_k + v_k, theta_max).
void lipRollout(const double* x0, const double* u, int n_stages, int u_stride, double a01, double a11, double b0,
                double b1, double theta_max, double* out);

/// The timed MPCC's roll-out (lipmpcc.planners.mpcc_timed: TimedFormulation.rollout after first_state): out[(N+1) × 6]
/// from the first state x_first (6) and the stage variables z[n_head + n_var * k + 0..4] = [uˣ, uʸ, u^θ, v, d]:
/// T_k = t_min + gain d_k, the LIP's exact step over T_k with ω = w (none when T_k ≤ 0), ϑ_{k+1} = min(ϑ_k + v_k,
/// theta_max). The file is also compiled with -fno-builtin: cosh and sinh are the C library's, as Python's math.
void timedLipRollout(const double* x_first, const double* z, int n_head, int n_var, int n_stages, double w,
                     double t_min, double gain, double theta_max, double* out);

}  // namespace lipmpcc::sqp
