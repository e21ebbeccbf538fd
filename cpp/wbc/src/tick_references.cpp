// See tick_references.hpp: every expression mirrors a Python one, operation by operation.
#include "lipmpcc/wbc/tick_references.hpp"

#include <cmath>

namespace lipmpcc::wbc::tickref {
namespace {

// Python's max(a, b) / min(a, b): `a` unless `b` is strictly larger / smaller.
inline double pyMax(double a, double b) { return b > a ? b : a; }
inline double pyMin(double a, double b) { return b < a ? b : a; }

// smoothstep5(tau): s, ds/dtau, d2s/dtau2
void smoothstep5(double tau, double out[3]) {
  const double t = pyMin(1.0, pyMax(0.0, tau));
  out[0] = std::pow(t, 3.0) * (10.0 + t * (-15.0 + 6.0 * t));
  out[1] = 30.0 * std::pow(t, 2.0) * std::pow(1.0 - t, 2.0);
  out[2] = 60.0 * t * (1.0 - t) * (1.0 - 2.0 * t);
}

// apex_bump(tau): b, db/dtau, d2b/dtau2
void apexBump(double tau, double out[3]) {
  const double t = pyMin(1.0, pyMax(0.0, tau));
  const double u = 1.0 - t;
  out[0] = 64.0 * std::pow(t, 3.0) * std::pow(u, 3.0);
  out[1] = 192.0 * std::pow(t, 2.0) * std::pow(u, 2.0) * (u - t);
  out[2] = 384.0 * t * u * (u * u - 3.0 * t * u + t * t);
}

// Quintic._evaluate_lists: (basis(t) @ c) with c (6 x 5, row-major), rows: position, velocity, acceleration
void quinticEvaluate(const double* c, double t0, double t, double out[3][5]) {
  const double s = pyMax(0.0, t - t0);
  const double s2 = s * s;
  const double s3 = s2 * s;
  const double basis[3][6] = {{1.0, s, s2, s3, s3 * s, s3 * s2},
                              {0.0, 1.0, 2.0 * s, 3.0 * s2, 4.0 * s3, 5.0 * s3 * s},
                              {0.0, 0.0, 2.0, 6.0 * s, 12.0 * s2, 20.0 * s3}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 5; ++j) {
      double acc = 0.0;
      for (int k = 0; k < 6; ++k) acc = std::fma(basis[i][k], c[5 * k + j], acc);
      out[i][j] = acc;
    }
}

}  // namespace

void lipEvaluate(const double* lip, double t, LipSample& out) {
  const double t0 = lip[0], w = lip[1], height = lip[2];
  const double cx = lip[3], cy = lip[4], vx = lip[5], vy = lip[6], px = lip[7], py = lip[8];
  const double tau = w * pyMax(0.0, t - t0);
  const double ch = std::cosh(tau), sh = std::sinh(tau);
  const double dx = cx - px, dy = cy - py;
  const double x = px + dx * ch + vx * sh / w;
  const double y = py + dy * ch + vy * sh / w;
  const double w2 = std::pow(w, 2.0);
  out.pos[0] = x;
  out.pos[1] = y;
  out.pos[2] = height;
  out.vel[0] = dx * w * sh + vx * ch;
  out.vel[1] = dy * w * sh + vy * ch;
  out.vel[2] = 0.0;
  out.acc[0] = w2 * (x - px);
  out.acc[1] = w2 * (y - py);
  out.acc[2] = 0.0;
}

void stepEvaluate(const double* step, double t, StepSample& out) {
  const double t_i = step[0], tau_i = step[1], t_end = step[2];
  const double* rdh = step + 3;  // (r0, d, h) per coordinate
  double tau = 1.0;              // PhaseClock.tau
  if (!(t_end <= t_i)) tau = pyMin(1.0, pyMax(0.0, tau_i + (1.0 - tau_i) * (t - t_i) / (t_end - t_i)));
  const double td = (t >= t_end || t_end <= t_i) ? 0.0 : (1.0 - tau_i) / (t_end - t_i);  // PhaseClock.tau_dot
  double sm[3], bump[3];
  smoothstep5(tau, sm);
  apexBump(tau, bump);
  const bool corrected = step[18] != 0.0 && t < step[20];
  double corr[3][5] = {};
  if (corrected) quinticEvaluate(step + 21, step[19], t, corr);
  out.tau = tau;
  for (int j = 0; j < 5; ++j) {
    const double r0 = rdh[3 * j], d = rdh[3 * j + 1], h = rdh[3 * j + 2];
    double r = r0 + d * sm[0] + h * bump[0];
    double dr = (d * sm[1] + h * bump[1]) * td;
    double ddr = (d * sm[2] + h * bump[2]) * td * td;
    if (corrected) {
      r = r + corr[0][j];
      dr = dr + corr[1][j];
      ddr = ddr + corr[2][j];
    }
    out.r[j] = r;
    out.dr[j] = dr;
    out.ddr[j] = ddr;
  }
}

void yawRotation(double yaw, double* rot9) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  const double rot[9] = {c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0};
  for (int i = 0; i < 9; ++i) rot9[i] = rot[i];
}

}  // namespace lipmpcc::wbc::tickref
