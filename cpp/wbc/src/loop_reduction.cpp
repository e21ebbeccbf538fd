// Elimination of the loop-dependent accelerations (Eigen only). See loop_reduction.hpp.
#include "lipmpcc/wbc/loop_reduction.hpp"

namespace lipmpcc::wbc {

namespace {

/// out = J Z = J_i + J_d G (k x n_i); drift += J_d g0.
template <typename JType, typename DriftType>
void reduceTask(const std::vector<int>& ind, const std::vector<int>& dep, const LoopReduction& ws,
                const Eigen::MatrixBase<JType>& J, Eigen::MatrixBase<DriftType>& drift, Mat& out) {
  out = J(Eigen::all, ind);
  out.noalias() += J(Eigen::all, dep) * ws.G;
  drift.noalias() += J(Eigen::all, dep) * ws.g0;
}

}  // namespace

bool reduceLoops(const WbcModel& model, const DynamicsTerms& t, LoopReduction& ws, DynamicsTerms& r) {
  const std::vector<int>& ind = model.independentIdxV();
  const std::vector<int>& dep = model.dependentIdxV();
  const auto ni = static_cast<Eigen::Index>(ind.size());

  // qdd_d = G a + g0
  ws.lu.compute(t.J_loop(Eigen::all, dep));
  ws.rcond = ws.lu.rcond();
  if (!(ws.rcond > kMinLoopRcond)) return false;
  ws.G = -ws.lu.solve(t.J_loop(Eigen::all, ind));
  ws.g0 = -ws.lu.solve(t.gamma_loop);

  // M_r = Z^T M Z, h_r = Z^T (h + M z0)
  ws.MZ = t.M(Eigen::all, ind);
  ws.MZ.noalias() += t.M(Eigen::all, dep) * ws.G;
  r.M = ws.MZ(ind, Eigen::all);
  r.M.noalias() += ws.G.transpose() * ws.MZ(dep, Eigen::all);
  r.M = 0.5 * (r.M + r.M.transpose()).eval();  // exact symmetry for the QP
  ws.hz = t.h;
  ws.hz.noalias() += t.M(Eigen::all, dep) * ws.g0;
  r.h = ws.hz(ind);
  r.h.noalias() += ws.G.transpose() * ws.hz(dep);

  Mat tmp;
  for (std::size_t f = 0; f < kNumFeet; ++f) {
    r.drift_sole[f] = t.drift_sole[f];
    reduceTask(ind, dep, ws, t.J_sole[f], r.drift_sole[f], tmp);
    r.J_sole[f] = tmp;
    r.vel_sole[f] = t.vel_sole[f];
    r.p_sole[f] = t.p_sole[f];
    r.R_sole[f] = t.R_sole[f];
  }
  r.drift_com = t.drift_com;
  reduceTask(ind, dep, ws, t.J_com, r.drift_com, tmp);
  r.J_com = tmp;
  r.drift_torso = t.drift_torso;
  reduceTask(ind, dep, ws, t.J_torso, r.drift_torso, tmp);
  r.J_torso = tmp;
  r.drift_k = t.drift_k;
  reduceTask(ind, dep, ws, t.A_ang, r.drift_k, tmp);
  r.A_ang = tmp;
  r.com = t.com;
  r.vcom = t.vcom;
  r.R_torso = t.R_torso;
  r.w_torso = t.w_torso;
  r.k_com = t.k_com;

  // The loops are eliminated: no extra equalities in the QP.
  r.J_loop.resize(0, ni);
  r.gamma_loop.resize(0);
  r.loop_residual = t.loop_residual;
  r.J_extra.resize(0, ni);
  r.gamma_extra.resize(0);

  // reg |qdd|^2 = reg |Z a + z0|^2 = reg (a^T (I + G^T G) a + 2 (G^T g0)^T a) + const
  r.qdd_metric.noalias() = ws.G.transpose() * ws.G;
  r.qdd_metric.diagonal().array() += 1.0;
  r.qdd_metric_g.noalias() = ws.G.transpose() * ws.g0;
  return true;
}

void expandAccelerations(const WbcModel& model, const LoopReduction& ws, const Eigen::Ref<const Vec>& a,
                         Vec& qdd) {
  qdd.resize(model.nv());
  qdd(model.independentIdxV()) = a;
  Vec qd = ws.g0;
  qd.noalias() += ws.G * a;
  qdd(model.dependentIdxV()) = qd;
}

void loopForcesFromResidual(const WbcModel& model, const LoopReduction& ws, const Eigen::Ref<const Vec>& residual,
                            Vec& lambda) {
  const Vec rd = residual(model.dependentIdxV());
  lambda = ws.lu.transpose().solve(rd);
}

}  // namespace lipmpcc::wbc
