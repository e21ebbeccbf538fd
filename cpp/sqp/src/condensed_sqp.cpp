// CondensedSqp: the solve loop of lipmpcc/solvers/condensed_sqp.py, step for step (see the header).
extern "C" {
#include "api.h"
#include "utils.h"
}

#include "lipmpcc/sqp/condensed_sqp.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace lipmpcc::sqp {

namespace {

/// Finite stand-in for an infinite bound of a QP step (condensed_sqp.py's _BIG).
constexpr double kBig = 1e4;
using ColMap = Eigen::Map<const Eigen::MatrixXd>;

/// numpy's pairwise sum of ``a[0..n)`` (the order of np.sum on a contiguous float64 array).
double pairwiseSum(const double* a, Eigen::Index n) {
  if (n < 8) {
    double res = 0.0;
    for (Eigen::Index i = 0; i < n; ++i) res += a[i];
    return res;
  }
  if (n <= 128) {
    double r[8];
    for (int j = 0; j < 8; ++j) r[j] = a[j];
    Eigen::Index i = 8;
    for (; i < n - (n % 8); i += 8)
      for (int j = 0; j < 8; ++j) r[j] += a[i + j];
    double res = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]));
    for (; i < n; ++i) res += a[i];
    return res;
  }
  Eigen::Index n2 = n / 2;
  n2 -= n2 % 8;
  return pairwiseSum(a, n2) + pairwiseSum(a + n2, n - n2);
}

}  // namespace

/// DAQP's data for min ½ΔᵀHΔ + ∇fᵀΔ s.t. blo ≤ [Δ, ∇g Δ] ≤ bhi (the first nu rows simple bounds), and
/// with warm_start its persistent workspace (the working set of the last QP).
struct CondensedSqp::Qp {
  DAQPSettings settings{};
  DAQPProblem problem{};
  DAQPWorkspace work{};  // zero-initialised: every pointer NULL until setup
  bool set_up = false;
  Vec blo, bhi, x, lam;
  std::vector<int> sense;
  int iterations = 0;

  ~Qp() { release(); }

  void release() {
    if (!set_up) return;
    work.settings = nullptr;  // ours, not DAQP's to free
    free_daqp_workspace(&work);
    free_daqp_ldp(&work);
    work = DAQPWorkspace{};
    set_up = false;
  }

  /// Runs DAQP on the workspace's LDP; returns its exit flag.
  int run() {
    DAQPResult res{};
    res.x = x.data();
    res.lam = lam.data();
    daqp_solve(&res, &work);
    iterations += res.iter;
    return res.exitflag;
  }

  /// A fresh workspace (empty working set) and its solve; returns DAQP's flag.
  int cold() {
    release();
    std::fill(sense.begin(), sense.end(), 0);
    work.settings = &settings;
    const int flag = setup_daqp(&problem, &work, nullptr);
    if (flag < 0) {
      work.settings = nullptr;
      free_daqp_ldp(&work);  // setup_daqp freed the rest
      work = DAQPWorkspace{};
      return flag;
    }
    set_up = true;
    return run();
  }

  /// From the working set of the previous QP: the whole LDP formed again, or with ``bounds_only`` (same H,
  /// ∇f and ∇g) only its right-hand side; a cold solve when that fails.
  int warm(bool bounds_only) {
    if (!set_up) return cold();
    const int mask = bounds_only ? DAQP_UPDATE_d : DAQP_UPDATE_Rinv + DAQP_UPDATE_M + DAQP_UPDATE_v + DAQP_UPDATE_d;
    int flag = daqp_update_ldp(mask, &work, &problem);
    if (flag >= 0) flag = run();
    return flag == DAQP_EXIT_OPTIMAL ? flag : cold();
  }
};

CondensedSqp::CondensedSqp(std::shared_ptr<CasadiFunction> terms, std::shared_ptr<CasadiFunction> merit,
                           const Vec& lbg, const Vec& ubg, const Vec& lbu, const Vec& ubu, const SqpSettings& settings)
    : terms_(std::move(terms)), merit_(std::move(merit)), settings_(settings), qp_(std::make_unique<Qp>()) {
  if (!terms_ || !merit_) throw std::invalid_argument("CondensedSqp: terms and merit functions are required");
  nu_ = static_cast<int>(lbu.size());
  m_ = static_cast<int>(lbg.size());
  n_params_ = terms_->nIn() - 2;
  const bool ok = n_params_ >= 0 && ubu.size() == nu_ && ubg.size() == m_ && terms_->nOut() == 5 &&
                  merit_->nOut() == 2 && merit_->nIn() == n_params_ + 1 && terms_->inSize(0) == nu_ &&
                  merit_->inSize(0) == nu_ && terms_->inSize(n_params_ + 1) == m_ && terms_->outSize(0) == 1 &&
                  terms_->outSize(1) == nu_ && terms_->outSize(2) == m_ && terms_->outSize(3) == m_ * nu_ &&
                  terms_->outSize(4) == nu_ * nu_ && merit_->outSize(0) == 1 && merit_->outSize(1) == m_;
  if (!ok) throw std::invalid_argument("CondensedSqp: the functions' sizes do not match n = " + std::to_string(nu_) +
                                       " inputs and m = " + std::to_string(m_) + " constraints");
  for (int i = 0; i < n_params_; ++i)
    if (merit_->inSize(1 + i) != terms_->inSize(1 + i))
      throw std::invalid_argument("CondensedSqp: parameter " + std::to_string(i) + " differs between the functions");
  lbg_ = lbg;
  ubg_ = ubg;
  auto finite_or = [](const Vec& v, double big) {
    return v.unaryExpr([big](double x) { return std::isfinite(x) ? x : big; }).eval();
  };
  lbu_ = finite_or(lbu, -kBig);
  ubu_ = finite_or(ubu, kBig);
  lo_g_ = finite_or(lbg, -kBig);
  hi_g_ = finite_or(ubg, kBig);
  for (int i = 0; i < m_; ++i) {
    if (!std::isfinite(lbg[i])) free_lo_rows_.push_back(nu_ + i);
    if (!std::isfinite(ubg[i])) free_hi_rows_.push_back(nu_ + i);
  }
  grad_.resize(nu_);
  g_.resize(m_);
  g_merit_.resize(m_);
  jg_col_.resize(m_ * nu_);
  h_col_.resize(nu_ * nu_);
  args_.assign(static_cast<std::size_t>(n_params_ + 2), nullptr);
  daqp_default_settings(&qp_->settings);
  qp_->blo.resize(nu_ + m_);
  qp_->bhi.resize(nu_ + m_);
  qp_->x.resize(nu_);
  qp_->lam.resize(nu_ + m_);
  qp_->sense.assign(static_cast<std::size_t>(nu_ + m_), 0);
}

CondensedSqp::~CondensedSqp() = default;

double CondensedSqp::violation(const Vec& g) const {
  const Vec below = (lbg_ - g).cwiseMax(0.0);
  const Vec above = (g - ubg_).cwiseMax(0.0);
  return pairwiseSum(below.data(), below.size()) + pairwiseSum(above.data(), above.size());
}

void CondensedSqp::qpBounds(const Vec& u, const Vec& g) {
  Vec& lo = qp_->blo;
  Vec& hi = qp_->bhi;
  lo.head(nu_) = lbu_ - u;
  lo.tail(m_) = lo_g_ - g;
  hi.head(nu_) = ubu_ - u;
  hi.tail(m_) = hi_g_ - g;
  for (int r : free_lo_rows_) lo[r] = -kBig;
  for (int r : free_hi_rows_) hi[r] = kBig;
}

int CondensedSqp::solveQp(const Vec& grad, SqpResult& out, bool bounds_only) {
  Qp& q = *qp_;
  DAQPProblem& problem = q.problem;
  problem.n = nu_;
  problem.m = nu_ + m_;
  problem.ms = nu_;
  const bool factored = settings_.convexification == Convexification::ModifiedCholesky;
  problem.H = factored ? rpack_.data() : h_.data();
  problem.f = const_cast<double*>(grad.data());
  problem.A = jg_.data();
  problem.bupper = q.bhi.data();
  problem.blower = q.blo.data();
  problem.sense = q.sense.data();
  problem.break_points = nullptr;
  problem.nh = 0;
  problem.problem_type = factored ? 2 : 0;  // 2: H holds R with H = RᵀR
  q.iterations = 0;
  const auto t0 = std::chrono::steady_clock::now();
  int flag = 0;
  if (settings_.warm_start) {
    flag = q.warm(bounds_only);
  } else {
    DAQPResult res{};
    res.x = q.x.data();
    res.lam = q.lam.data();
    daqp_quadprog(&res, &problem, &q.settings);  // cold, as daqp.solve (DAQP copies sense)
    q.iterations = res.iter;
    flag = res.exitflag;
  }
  out.qp_time += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out.qp_iters += q.iterations;
  if (flag < 1) q.release();  // no useful working set after a failure
  return flag;
}

void CondensedSqp::replaceFunctions(std::shared_ptr<CasadiFunction> terms, std::shared_ptr<CasadiFunction> merit) {
  auto same = [](const CasadiFunction& a, const CasadiFunction& b) {
    if (a.nIn() != b.nIn() || a.nOut() != b.nOut()) return false;
    for (int i = 0; i < a.nIn(); ++i)
      if (a.inSize(i) != b.inSize(i)) return false;
    for (int j = 0; j < a.nOut(); ++j)
      if (a.outShape(j) != b.outShape(j)) return false;
    return true;
  };
  if ((terms && !same(*terms, *terms_)) || (merit && !same(*merit, *merit_)))
    throw std::invalid_argument("CondensedSqp::replaceFunctions: a function's inputs or outputs differ");
  if (terms) terms_ = std::move(terms);
  if (merit) merit_ = std::move(merit);
}

void CondensedSqp::evalMerit(const Vec& u, double& cost, Vec& g) {
  args_[0] = u.data();
  double* res[2] = {&cost, g.data()};
  merit_->eval(args_.data(), res);
}

void CondensedSqp::modifiedCholesky() {
  const int n = nu_;
  const ColMap H(h_col_.data(), n, n);
  chol_.resize(n, n);
  double gamma = 0.0, xi = 0.0;
  for (int j = 0; j < n; ++j) {
    chol_(j, j) = H(j, j);
    gamma = std::max(gamma, std::abs(H(j, j)));
    for (int i = j + 1; i < n; ++i) {
      chol_(i, j) = H(i, j);
      xi = std::max(xi, std::abs(H(i, j)));
    }
  }
  const double nu = n > 1 ? std::sqrt(static_cast<double>(n) * n - 1.0) : 0.0;
  const double beta2 = std::max({gamma, n > 1 ? xi / nu : 0.0, std::numeric_limits<double>::epsilon()});
  rpack_.resize(static_cast<Eigen::Index>(n) * (n + 1) / 2);
  Eigen::Index disp = 0;  // the diagonal of row j of the packed R
  for (int j = 0; j < n; ++j) {
    // column j holds c_ij = a_ij − Σ_{s<j} d_s l_is l_js (i ≥ j): the right-looking updates so far
    double theta = 0.0;
    for (int i = j + 1; i < n; ++i) theta = std::max(theta, std::abs(chol_(i, j)));
    const double d = std::max({std::abs(chol_(j, j)), theta * theta / beta2, settings_.eig_floor});
    const double sd = std::sqrt(d), inv_d = 1.0 / d, inv_sd = 1.0 / sd;
    rpack_[disp] = sd;
    for (int i = j + 1; i < n; ++i) rpack_[disp + (i - j)] = chol_(i, j) * inv_sd;  // √d_j l_ij
    for (int k = j + 1; k < n; ++k) {  // the trailing lower triangle −= c_ij c_kj / d_j
      const double f = chol_(k, j) * inv_d;
      if (f == 0.0) continue;
      for (int i = k; i < n; ++i) chol_(i, k) -= chol_(i, j) * f;
    }
    disp += n - j;
  }
}

void CondensedSqp::convexify() {
  if (settings_.convexification == Convexification::ModifiedCholesky) {
    modifiedCholesky();
    return;
  }
  const ColMap H(h_col_.data(), nu_, nu_);
  if (settings_.partial_eigen && partial_.compute(H, settings_.eig_floor, h_partial_)) {
    h_ = h_partial_;
    return;
  }
  eig_.compute(H);  // the lower triangle, as numpy's eigh (a kept solver: no allocation)
  const Eigen::MatrixXd& V = eig_.eigenvectors();
  vw_.noalias() = V * eig_.eigenvalues().cwiseMax(settings_.eig_floor).asDiagonal();
  h_.noalias() = vw_ * V.transpose();
}

bool CondensedSqp::contracted(double size, double prev_size, double alpha, const Merit& merit) const {
  if (settings_.rate_stop == 0.0 || alpha != 1.0 || !merit.valid || merit.violation >= 5e-7 ||
      !std::isfinite(prev_size))
    return false;
  const double r = size / prev_size;
  return r < 0.5 && size * r / (1.0 - r) < settings_.rate_stop * settings_.tol;
}

bool CondensedSqp::correctedStep(const Vec& u, const Vec& grad, const Vec& g_c, double nu_merit, double phi_max,
                                 Step& step, SqpResult& out) {
  qpBounds(u, g_c);
  if (solveQp(grad, out, true) < 1) return false;
  const Vec d = qp_->x;
  const Vec u_c = u + d;
  double c_n = 0.0;
  evalMerit(u_c, c_n, g_merit_);
  const double v_n = violation(g_merit_);
  if (c_n + nu_merit * v_n > phi_max) return false;
  step = Step{1.0, d, qp_->lam.tail(m_), Merit{true, u_c, c_n, v_n}};
  return true;
}

CondensedSqp::Step CondensedSqp::lineSearch(const Vec& u, const Vec& du, const Vec& grad, const Vec& g, double cost,
                                            const Vec& lam_qp, SqpResult& out) {
  const double lam_max = lam_qp.size() > 0 ? std::max(lam_qp.cwiseAbs().maxCoeff(), 0.0) : 0.0;
  const double nu_merit = std::max(1e2, 2.0 * lam_max);
  const double viol = violation(g);
  const double phi0 = cost + nu_merit * viol;
  const double dphi = grad.dot(du) - nu_merit * viol;
  const double slack = 1e-12 * std::max(1.0, std::abs(phi0));
  const double du_max = du.size() > 0 ? du.cwiseAbs().maxCoeff() : 0.0;
  double alpha = 1.0;
  for (int k = 0; k < 10; ++k) {
    const Vec step = alpha * du;
    const Vec u_n = u + step;
    double c_n = 0.0;
    evalMerit(u_n, c_n, g_merit_);
    const double v_n = violation(g_merit_);
    const double phi_n = c_n + nu_merit * v_n;
    if (phi_n <= phi0 + 1e-4 * alpha * std::min(dphi, 0.0) + slack)
      return Step{alpha, step, lam_qp, Merit{true, u_n, c_n, v_n}};
    if (alpha == 1.0 && v_n > viol && du_max < settings_.second_order_correction) {
      const Vec g_c = g_merit_ - jg_ * du;
      Step corrected;
      if (correctedStep(u, grad, g_c, nu_merit, phi0 + 1e-4 * std::min(dphi, 0.0) + slack, corrected, out))
        return corrected;
    }
    alpha *= 0.5;
  }
  return Step{alpha, alpha * du, lam_qp, Merit{}};
}

SqpResult CondensedSqp::solve(const Vec& u0, const std::vector<Vec>& params, const Vec& lam0, bool record_trace) {
  if (u0.size() != nu_ || lam0.size() != m_ || static_cast<int>(params.size()) != n_params_)
    throw std::invalid_argument("CondensedSqp::solve: expected u0 of size " + std::to_string(nu_) + ", " +
                                std::to_string(n_params_) + " parameters and lam of size " + std::to_string(m_));
  for (int i = 0; i < n_params_; ++i) {
    if (params[static_cast<std::size_t>(i)].size() != paramSize(i))
      throw std::invalid_argument("CondensedSqp::solve: parameter " + std::to_string(i) + " must have " +
                                  std::to_string(paramSize(i)) + " values");
    if (!params[static_cast<std::size_t>(i)].allFinite())
      throw std::invalid_argument("CondensedSqp::solve: parameter " + std::to_string(i) + " must be finite");
    args_[static_cast<std::size_t>(1 + i)] = params[static_cast<std::size_t>(i)].data();
  }
  if (!u0.allFinite() || !lam0.allFinite())
    throw std::invalid_argument("CondensedSqp::solve: u0 and lam must be finite");
  SqpResult out;
  Vec u = u0.cwiseMax(lbu_).cwiseMin(ubu_);
  Vec lam = lam0;
  std::string status = "max_iter";
  int iterations = 0;
  Merit merit;
  double prev_size = std::numeric_limits<double>::infinity();
  for (int it = 1; it <= settings_.max_iter; ++it) {
    iterations = it;
    args_[0] = u.data();
    args_[static_cast<std::size_t>(n_params_ + 1)] = lam.data();
    double* res[5] = {&cost_, grad_.data(), g_.data(), jg_col_.data(), h_col_.data()};
    terms_->eval(args_.data(), res);
    jg_ = ColMap(jg_col_.data(), m_, nu_);
    convexify();
    qpBounds(u, g_);
    const int flag = solveQp(grad_, out, false);
    if (flag < 1) {
      out.status = "qp_failed (daqp exitflag " + std::to_string(flag) + ")";
      out.iterations = it;
      out.cost = cost_;
      out.u = u;
      out.lam = Vec::Zero(m_);
      return out;
    }
    const Vec du = qp_->x;
    const double qp_iterations = qp_->iterations;
    Step s = lineSearch(u, du, grad_, g_, cost_, qp_->lam.tail(m_), out);
    u = (u + s.step).cwiseMax(lbu_).cwiseMin(ubu_);
    lam = lam + s.alpha * (s.lam_qp - lam);
    merit = std::move(s.merit);
    if (record_trace) out.trace.push_back(TraceRow{it, s.alpha, du.cwiseAbs().maxCoeff(), qp_iterations});
    const double size = s.step.size() > 0 ? s.step.cwiseAbs().maxCoeff() : 0.0;
    if (size < settings_.tol || contracted(size, prev_size, s.alpha, merit)) {
      status = "converged";
      break;
    }
    prev_size = size;
  }
  double c_f = 0.0, viol = 0.0;
  if (merit.valid && merit.point == u) {  // the line search evaluated this very point
    c_f = merit.cost;
    viol = merit.violation;
  } else {
    args_[0] = u.data();
    evalMerit(u, c_f, g_merit_);
    viol = violation(g_merit_);
  }
  const bool feasible = viol < 1e-6;
  out.found = feasible && status == "converged";
  out.status = feasible ? status : "infeasible (" + status + ")";
  out.iterations = iterations;
  out.cost = c_f;
  out.u = u;
  out.lam = out.found ? lam : Vec::Zero(m_);
  return out;
}

}  // namespace lipmpcc::sqp
