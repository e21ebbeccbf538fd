// lipRollout and timedLipRollout (see lip_rollout.hpp): compiled with -ffp-contract=off -fno-builtin.
#include "lipmpcc/sqp/lip_rollout.hpp"

#include <cmath>

namespace lipmpcc::sqp {

void lipRollout(const double* x0, const double* u, int n_stages, int u_stride, double a01, double a11, double b0,
                double b1, double theta_max, double* out) {
  double x[6];
  for (int i = 0; i < 6; ++i) out[i] = x[i] = x0[i];
  for (int k = 0; k < n_stages; ++k) {
    const double* uk = u + static_cast<long>(k) * u_stride;
    const double ux = uk[0], uy = uk[1], uth = uk[2], v = uk[3];
    const double theta = x[5] + v;
    // the reference's min(a, b): b only when b < a
    const double next[6] = {(x[0] + a01 * x[1]) + b0 * ux, a11 * x[1] + b1 * ux, (x[2] + a01 * x[3]) + b0 * uy,
                            a11 * x[3] + b1 * uy, x[4] + uth, theta_max < theta ? theta_max : theta};
    double* row = out + 6L * (k + 1);
    for (int i = 0; i < 6; ++i) row[i] = x[i] = next[i];
  }
}

void timedLipRollout(const double* x_first, const double* z, int n_head, int n_var, int n_stages, double w,
                     double t_min, double gain, double theta_max, double* out) {
  double x[6];
  for (int i = 0; i < 6; ++i) out[i] = x[i] = x_first[i];
  for (int k = 0; k < n_stages; ++k) {
    const double* zk = z + n_head + static_cast<long>(n_var) * k;
    const double ux = zk[0], uy = zk[1], uth = zk[2], v = zk[3], d = zk[4];
    const double T = t_min + gain * d;
    double next[6];
    if (T <= 0.0) {
      for (int i = 0; i < 5; ++i) next[i] = x[i];
    } else {  // _lip_step_list's operations, in its order
      const double ch = std::cosh(w * T), sh = std::sinh(w * T);
      const double a = sh / w, b = 1.0 - ch, c = -w * sh;
      next[0] = (x[0] + a * x[1]) + b * ux;
      next[1] = ch * x[1] + c * ux;
      next[2] = (x[2] + a * x[3]) + b * uy;
      next[3] = ch * x[3] + c * uy;
      next[4] = x[4] + uth;
    }
    const double theta = x[5] + v;
    next[5] = theta_max < theta ? theta_max : theta;
    double* row = out + 6L * (k + 1);
    for (int i = 0; i < 6; ++i) row[i] = x[i] = next[i];
  }
}

}  // namespace lipmpcc::sqp
