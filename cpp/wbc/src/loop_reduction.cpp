// Elimination of the loop-dependent accelerations (Eigen only). See loop_reduction.hpp.
//
// Every matrix is first permuted to the order [independent | dependent] (one gather into a
// preallocated buffer), so that the products below are plain block products without temporaries.
#include "lipmpcc/wbc/loop_reduction.hpp"

namespace lipmpcc::wbc {

namespace {

/// Columns of J in the order [independent | dependent] into P (preallocated when sizes repeat).
template <typename JType>
void permuteCols(const Eigen::MatrixBase<JType>& J, const std::vector<int>& order, Mat& P) {
  P.resize(J.rows(), static_cast<Eigen::Index>(order.size()));
  for (std::size_t c = 0; c < order.size(); ++c) P.col(static_cast<Eigen::Index>(c)) = J.col(order[c]);
}

/// out = J Z = J_i + J_d G; drift += J_d g0 (J given permuted as P).
template <typename OutType, typename DriftType>
void reduceTask(const Mat& P, Eigen::Index ni, const LoopReduction& ws, OutType& out,
                Eigen::MatrixBase<DriftType>& drift) {
  const Eigen::Index nd = P.cols() - ni;
  out = P.leftCols(ni);
  out.noalias() += P.rightCols(nd) * ws.G;
  drift.noalias() += P.rightCols(nd) * ws.g0;
}

}  // namespace

bool reduceLoops(const WbcModel& model, const DynamicsTerms& t, LoopReduction& ws, DynamicsTerms& r) {
  const std::vector<int>& ind = model.independentIdxV();
  const std::vector<int>& dep = model.dependentIdxV();
  const auto ni = static_cast<Eigen::Index>(ind.size());
  const auto nd = static_cast<Eigen::Index>(dep.size());
  if (ws.order.size() != ind.size() + dep.size()) {
    ws.order = ind;
    ws.order.insert(ws.order.end(), dep.begin(), dep.end());
  }

  // qdd_d = G a + g0 from J_d qdd_d + J_i a + gamma = 0
  permuteCols(t.J_loop, ws.order, ws.P);
  ws.lu.compute(ws.P.rightCols(nd));
  ws.rcond = ws.lu.rcond();
  if (!(ws.rcond > kMinLoopRcond)) return false;
  ws.G = ws.lu.solve(ws.P.leftCols(ni));
  ws.G *= -1.0;
  ws.g0 = ws.lu.solve(t.gamma_loop);
  ws.g0 *= -1.0;

  // M_r = Z^T M Z, h_r = Z^T (h + M z0), with M permuted on both sides
  ws.Mp.resize(t.M.rows(), t.M.cols());
  for (std::size_t c = 0; c < ws.order.size(); ++c) {
    const auto cc = static_cast<Eigen::Index>(c);
    for (std::size_t k = 0; k < ws.order.size(); ++k) ws.Mp(static_cast<Eigen::Index>(k), cc) = t.M(ws.order[k], ws.order[c]);
  }
  ws.hz.resize(t.h.size());
  for (std::size_t k = 0; k < ws.order.size(); ++k) ws.hz[static_cast<Eigen::Index>(k)] = t.h[ws.order[k]];
  ws.hz.noalias() += ws.Mp.rightCols(nd) * ws.g0;  // h + M z0 (permuted)
  ws.MZ = ws.Mp.leftCols(ni);                       // M Z (permuted rows)
  ws.MZ.noalias() += ws.Mp.rightCols(nd) * ws.G;
  r.M = ws.MZ.topRows(ni);
  r.M.noalias() += ws.G.transpose() * ws.MZ.bottomRows(nd);
  r.M.triangularView<Eigen::StrictlyLower>() = r.M.transpose();  // exact symmetry for the QP
  r.h = ws.hz.head(ni);
  r.h.noalias() += ws.G.transpose() * ws.hz.tail(nd);

  for (std::size_t f = 0; f < kNumFeet; ++f) {
    r.drift_sole[f] = t.drift_sole[f];
    permuteCols(t.J_sole[f], ws.order, ws.P);
    reduceTask(ws.P, ni, ws, r.J_sole[f], r.drift_sole[f]);
    r.vel_sole[f] = t.vel_sole[f];
    r.p_sole[f] = t.p_sole[f];
    r.R_sole[f] = t.R_sole[f];
  }
  r.drift_com = t.drift_com;
  permuteCols(t.J_com, ws.order, ws.P);
  reduceTask(ws.P, ni, ws, r.J_com, r.drift_com);
  r.drift_torso = t.drift_torso;
  permuteCols(t.J_torso, ws.order, ws.P);
  reduceTask(ws.P, ni, ws, r.J_torso, r.drift_torso);
  r.drift_k = t.drift_k;
  permuteCols(t.A_ang, ws.order, ws.P);
  reduceTask(ws.P, ni, ws, r.A_ang, r.drift_k);
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
  r.qdd_metric.resize(ni, ni);
  r.qdd_metric.setIdentity();
  r.qdd_metric.noalias() += ws.G.transpose() * ws.G;
  r.qdd_metric_g.noalias() = ws.G.transpose() * ws.g0;
  return true;
}

void expandAccelerations(const WbcModel& model, const LoopReduction& ws, const Eigen::Ref<const Vec>& a,
                         Vec& qdd) {
  const std::vector<int>& ind = model.independentIdxV();
  const std::vector<int>& dep = model.dependentIdxV();
  qdd.resize(model.nv());
  for (std::size_t k = 0; k < ind.size(); ++k) qdd[ind[k]] = a[static_cast<Eigen::Index>(k)];
  for (std::size_t k = 0; k < dep.size(); ++k) {
    const auto kk = static_cast<Eigen::Index>(k);
    qdd[dep[k]] = ws.g0[kk] + ws.G.row(kk).dot(a);
  }
}

void loopForcesFromResidual(const WbcModel& model, const LoopReduction& ws, const Eigen::Ref<const Vec>& residual,
                            Vec& lambda) {
  const std::vector<int>& dep = model.dependentIdxV();
  Vec rd(static_cast<Eigen::Index>(dep.size()));
  for (std::size_t k = 0; k < dep.size(); ++k) rd[static_cast<Eigen::Index>(k)] = residual[dep[k]];
  lambda = ws.lu.transpose().solve(rd);  // J_d^T lambda = residual_d
}

}  // namespace lipmpcc::wbc
