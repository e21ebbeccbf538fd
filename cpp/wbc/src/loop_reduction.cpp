// Elimination of the loop-dependent accelerations (Eigen only). See loop_reduction.hpp.
//
// Everything stays in the velocity order (index lists instead of permuted copies), and the
// products with G run over its exact non-zeros only (LoopReduction).
#include "lipmpcc/wbc/loop_reduction.hpp"

namespace lipmpcc::wbc {

namespace {

/// out = J Z = J_i + J_d G; drift += J_d g0 (J: rows x nv, velocity order).
template <typename JType, typename OutType, typename DriftType>
void reduceTask(const Eigen::MatrixBase<JType>& J, const std::vector<int>& ind, const std::vector<int>& dep,
                const LoopReduction& ws, OutType& out, Eigen::MatrixBase<DriftType>& drift) {
  const auto ni = static_cast<Eigen::Index>(ind.size());
  out.resize(J.rows(), ni);
  for (Eigen::Index j = 0; j < ni; ++j) out.col(j) = J.col(ind[static_cast<std::size_t>(j)]);
  for (std::size_t c = 0; c < ws.g_cols.size(); ++c) {
    const Eigen::Index j = ws.g_cols[c];
    for (int p = ws.csc_start[c]; p < ws.csc_start[c + 1]; ++p) {
      const int k = ws.csc_row[static_cast<std::size_t>(p)];
      out.col(j) += ws.G(k, j) * J.col(dep[static_cast<std::size_t>(k)]);
    }
  }
  for (std::size_t k = 0; k < dep.size(); ++k) {
    const double gk = ws.g0[static_cast<Eigen::Index>(k)];
    if (gk != 0.0) drift += gk * J.col(dep[k]);
  }
}

}  // namespace

bool reduceLoops(const WbcModel& model, const DynamicsTerms& t, LoopReduction& ws, DynamicsTerms& r) {
  const std::vector<int>& ind = model.independentIdxV();
  const std::vector<int>& dep = model.dependentIdxV();
  const auto ni = static_cast<Eigen::Index>(ind.size());
  const auto nd = static_cast<Eigen::Index>(dep.size());
  const Eigen::Index nv = t.M.rows();

  // qdd_d = G a + g0 from J_d qdd_d + J_i a + gamma = 0. A zero column of J_i gives a zero column
  // of G: only the others are solved for.
  ws.Jd.resize(nd, nd);
  for (Eigen::Index k = 0; k < nd; ++k) ws.Jd.col(k) = t.J_loop.col(dep[static_cast<std::size_t>(k)]);
  ws.g_cols.clear();
  for (Eigen::Index j = 0; j < ni; ++j)
    if ((t.J_loop.col(ind[static_cast<std::size_t>(j)]).array() != 0.0).any()) ws.g_cols.push_back(static_cast<int>(j));
  const auto nc = static_cast<Eigen::Index>(ws.g_cols.size());
  ws.Ji.resize(nd, nc);
  for (Eigen::Index c = 0; c < nc; ++c)
    ws.Ji.col(c) = t.J_loop.col(ind[static_cast<std::size_t>(ws.g_cols[static_cast<std::size_t>(c)])]);
  ws.lu.compute(ws.Jd);
  ws.rcond = ws.lu.rcond();
  if (!(ws.rcond > kMinLoopRcond)) return false;
  ws.Gc = ws.lu.solve(ws.Ji);
  ws.G.setZero(nd, ni);
  for (Eigen::Index c = 0; c < nc; ++c) ws.G.col(ws.g_cols[static_cast<std::size_t>(c)]) = -ws.Gc.col(c);
  ws.g0 = ws.lu.solve(t.gamma_loop);
  ws.g0 *= -1.0;

  // The exact non-zeros of G, by column and by row (ascending indices).
  ws.csc_start.assign(1, 0);
  ws.csc_row.clear();
  for (Eigen::Index c = 0; c < nc; ++c) {
    const Eigen::Index j = ws.g_cols[static_cast<std::size_t>(c)];
    for (Eigen::Index k = 0; k < nd; ++k)
      if (ws.G(k, j) != 0.0) ws.csc_row.push_back(static_cast<int>(k));
    ws.csc_start.push_back(static_cast<int>(ws.csc_row.size()));
  }
  ws.csr_start.assign(1, 0);
  ws.csr_col.clear();
  for (Eigen::Index k = 0; k < nd; ++k) {
    for (Eigen::Index c = 0; c < nc; ++c) {
      const int j = ws.g_cols[static_cast<std::size_t>(c)];
      if (ws.G(k, j) != 0.0) ws.csr_col.push_back(j);
    }
    ws.csr_start.push_back(static_cast<int>(ws.csr_col.size()));
  }

  // M_r = Z^T M Z, h_r = Z^T (h + M z0)
  ws.MZ.resize(nv, ni);  // M Z = M_:i + M_:d G
  for (Eigen::Index j = 0; j < ni; ++j) ws.MZ.col(j) = t.M.col(ind[static_cast<std::size_t>(j)]);
  for (Eigen::Index c = 0; c < nc; ++c) {
    const Eigen::Index j = ws.g_cols[static_cast<std::size_t>(c)];
    for (int p = ws.csc_start[static_cast<std::size_t>(c)]; p < ws.csc_start[static_cast<std::size_t>(c) + 1]; ++p) {
      const int k = ws.csc_row[static_cast<std::size_t>(p)];
      ws.MZ.col(j) += ws.G(k, j) * t.M.col(dep[static_cast<std::size_t>(k)]);
    }
  }
  ws.hz = t.h;  // h + M z0 = h + M_:d g0
  for (Eigen::Index k = 0; k < nd; ++k) {
    const double gk = ws.g0[k];
    if (gk != 0.0) ws.hz += gk * t.M.col(dep[static_cast<std::size_t>(k)]);
  }
  // Upper triangle of M_r = (M Z)_i + G^T (M Z)_d, then mirrored (exact symmetry for the QP).
  r.M.resize(ni, ni);
  for (Eigen::Index j = 0; j < ni; ++j) {
    for (Eigen::Index i = 0; i <= j; ++i) r.M(i, j) = ws.MZ(ind[static_cast<std::size_t>(i)], j);
    for (Eigen::Index k = 0; k < nd; ++k) {
      const double mz = ws.MZ(dep[static_cast<std::size_t>(k)], j);
      if (mz == 0.0) continue;
      for (int p = ws.csr_start[static_cast<std::size_t>(k)]; p < ws.csr_start[static_cast<std::size_t>(k) + 1]; ++p) {
        const int i = ws.csr_col[static_cast<std::size_t>(p)];
        if (i > j) break;
        r.M(i, j) += ws.G(k, i) * mz;
      }
    }
  }
  r.M.triangularView<Eigen::StrictlyLower>() = r.M.transpose();
  r.h.resize(ni);
  for (Eigen::Index i = 0; i < ni; ++i) r.h[i] = ws.hz[ind[static_cast<std::size_t>(i)]];
  for (Eigen::Index k = 0; k < nd; ++k) {
    const double hk = ws.hz[dep[static_cast<std::size_t>(k)]];
    for (int p = ws.csr_start[static_cast<std::size_t>(k)]; p < ws.csr_start[static_cast<std::size_t>(k) + 1]; ++p) {
      const int i = ws.csr_col[static_cast<std::size_t>(p)];
      r.h[i] += ws.G(k, i) * hk;
    }
  }

  for (std::size_t f = 0; f < kNumFeet; ++f) {
    r.drift_sole[f] = t.drift_sole[f];
    reduceTask(t.J_sole[f], ind, dep, ws, r.J_sole[f], r.drift_sole[f]);
    r.vel_sole[f] = t.vel_sole[f];
    r.p_sole[f] = t.p_sole[f];
    r.R_sole[f] = t.R_sole[f];
  }
  r.drift_com = t.drift_com;
  reduceTask(t.J_com, ind, dep, ws, r.J_com, r.drift_com);
  r.drift_torso = t.drift_torso;
  reduceTask(t.J_torso, ind, dep, ws, r.J_torso, r.drift_torso);
  r.drift_k = t.drift_k;
  reduceTask(t.A_ang, ind, dep, ws, r.A_ang, r.drift_k);
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
  r.qdd_metric.setIdentity(ni, ni);
  r.qdd_metric_g.setZero(ni);
  for (Eigen::Index k = 0; k < nd; ++k) {
    const int p0 = ws.csr_start[static_cast<std::size_t>(k)], p1 = ws.csr_start[static_cast<std::size_t>(k) + 1];
    for (int p = p0; p < p1; ++p) {
      const int i = ws.csr_col[static_cast<std::size_t>(p)];
      const double gki = ws.G(k, i);
      for (int p2 = p0; p2 < p1; ++p2) {
        const int i2 = ws.csr_col[static_cast<std::size_t>(p2)];
        r.qdd_metric(i2, i) += ws.G(k, i2) * gki;
      }
      r.qdd_metric_g[i] += gki * ws.g0[k];
    }
  }
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
    double s = 0.0;  // G.row(k) . a over the row's non-zeros
    for (int p = ws.csr_start[k]; p < ws.csr_start[k + 1]; ++p) {
      const int i = ws.csr_col[static_cast<std::size_t>(p)];
      s += ws.G(kk, i) * a[i];
    }
    qdd[dep[k]] = ws.g0[kk] + s;
  }
}

void loopForcesFromResidual(const WbcModel& model, LoopReduction& ws, const Eigen::Ref<const Vec>& residual,
                            Vec& lambda) {
  const std::vector<int>& dep = model.dependentIdxV();
  ws.rd.resize(static_cast<Eigen::Index>(dep.size()));
  for (std::size_t k = 0; k < dep.size(); ++k) ws.rd[static_cast<Eigen::Index>(k)] = residual[dep[k]];
  lambda = ws.lu.transpose().solve(ws.rd);  // J_d^T lambda = residual_d
}

}  // namespace lipmpcc::wbc
