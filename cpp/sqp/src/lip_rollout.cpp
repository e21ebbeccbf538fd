// lipRollout (see lip_rollout.hpp): compiled with -ffp-contract=off.
#include "lipmpcc/sqp/lip_rollout.hpp"

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

}  // namespace lipmpcc::sqp
