// PartialEigenClip and tqlrat (see the header).
#include "lipmpcc/sqp/eigen_clip.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

namespace lipmpcc::sqp {

int tqlrat(int n, double* d, double* e2) {
  // EISPACK tqlrat (Reinsch's rational QL, 1973), 0-based; the eigenvalues sorted by insertion as they converge
  if (n <= 1) return 0;
  e2[n - 1] = 0.0;
  const double eps = std::numeric_limits<double>::epsilon();
  double f = 0.0, t = 0.0, b = 0.0, c = 0.0;
  for (int l = 0; l < n; ++l) {
    const double h0 = std::abs(d[l]) + std::sqrt(e2[l]);
    if (t <= h0) {
      t = h0;
      b = eps * t;
      c = b * b;
    }
    int m = l;
    while (e2[m] > c) ++m;  // e2[n − 1] = 0 ends the search
    for (int j = 0; m != l; ++j) {
      if (j == 30) return l + 1;
      const int l1 = l + 1;
      double s = std::sqrt(e2[l]);
      double g = d[l];
      double p = (d[l1] - g) / (2.0 * s);
      double r = std::hypot(p, 1.0);
      d[l] = s / (p + std::copysign(r, p));
      double h = g - d[l];
      for (int i = l1; i < n; ++i) d[i] -= h;
      f += h;
      g = d[m];
      if (g == 0.0) g = b;
      h = g;
      s = 0.0;
      for (int i = m - 1; i >= l; --i) {  // the rational QL sweep
        p = g * h;
        r = p + e2[i];
        e2[i + 1] = s * r;
        s = e2[i] / r;
        d[i + 1] = h + s * (h + d[i]);
        g = d[i] - e2[i] / g;
        if (g == 0.0) g = b;
        h = g * p / r;
      }
      e2[l] = s * g;
      d[l] = h;
      if (h == 0.0 || std::abs(e2[l]) <= std::abs(c / h)) break;  // (guards the test against underflow)
      e2[l] = h * e2[l];
      if (e2[l] == 0.0) break;
    }
    const double p = d[l] + f;
    int i = l;
    for (; i > 0 && p < d[i - 1]; --i) d[i] = d[i - 1];
    d[i] = p;
  }
  return 0;
}

bool PartialEigenClip::inverseIteration(int c, double mu, double tnorm) {
  // (T − μI) = P L U with partial pivoting (LAPACK's dlagtf for a symmetric T): U has the bands u0, u1, u2
  const int n = static_cast<int>(diag_.size());
  const double eps = std::numeric_limits<double>::epsilon();
  double c0 = diag_[0] - mu, c1 = n > 1 ? sub_[0] : 0.0, c2 = 0.0;
  for (int i = 0; i < n - 1; ++i) {
    const double e = sub_[i], d1 = diag_[i + 1] - mu, e1 = i + 2 < n ? sub_[i + 1] : 0.0;
    if (std::abs(c0) >= std::abs(e)) {
      const double li = c0 != 0.0 ? e / c0 : 0.0;
      piv_[i] = 0;
      l_[i] = li;
      u0_[i] = c0, u1_[i] = c1, u2_[i] = c2;
      c0 = d1 - li * c1, c1 = e1 - li * c2, c2 = 0.0;
    } else {
      const double li = c0 / e;
      piv_[i] = 1;
      l_[i] = li;
      u0_[i] = e, u1_[i] = d1, u2_[i] = e1;
      c0 = c1 - li * d1, c1 = c2 - li * e1, c2 = 0.0;
    }
  }
  u0_[n - 1] = c0;
  const double tiny = eps * tnorm;
  for (int i = 0; i < n; ++i) {
    if (std::abs(u0_[i]) < tiny) u0_[i] = u0_[i] < 0.0 ? -tiny : tiny;
    u0_[i] = 1.0 / u0_[i];  // the solves multiply
  }
  // the earlier vectors of this eigenvalue's cluster (dstein's 1e-3 ‖T‖)
  const double cluster = 1e-3 * tnorm;
  int first = c;
  while (first > 0 && mus_[static_cast<std::size_t>(c)] - mus_[static_cast<std::size_t>(first - 1)] <= cluster) --first;
  // a start vector of pseudo-random entries in [−1, 1] (a fixed sequence per c)
  unsigned state = 2654435761u * static_cast<unsigned>(c + 1);
  for (int i = 0; i < n; ++i) {
    state = state * 1664525u + 1013904223u;
    x_[i] = static_cast<double>(state >> 8) / static_cast<double>(1u << 23) - 1.0;
  }
  for (int it = 0; it < 5; ++it) {
    for (int p = first; p < c; ++p) x_ -= z_.col(p).dot(x_) * z_.col(p);
    for (int i = 0; i < n - 1; ++i) {  // P L: the row operations
      if (piv_[i]) {
        const double t = x_[i];
        x_[i] = x_[i + 1];
        x_[i + 1] = t - l_[i] * x_[i];
      } else {
        x_[i + 1] -= l_[i] * x_[i];
      }
    }
    for (int i = n - 1; i >= 0; --i) {  // U
      double s = x_[i];
      if (i + 1 < n) s -= u1_[i] * x_[i + 1];
      if (i + 2 < n) s -= u2_[i] * x_[i + 2];
      x_[i] = s * u0_[i];
    }
    for (int p = first; p < c; ++p) x_ -= z_.col(p).dot(x_) * z_.col(p);
    const double norm = x_.norm();
    if (!(norm > 0.0) || !std::isfinite(norm)) return false;
    x_ /= norm;
    if (it == 0) continue;  // at least two solves
    // the residual ‖(T − λ)x‖∞ with the unperturbed λ
    const double lam = vals_[c];
    double res = 0.0;
    for (int i = 0; i < n; ++i) {
      double r = (diag_[i] - lam) * x_[i];
      if (i > 0) r += sub_[i - 1] * x_[i - 1];
      if (i + 1 < n) r += sub_[i] * x_[i + 1];
      res = std::max(res, std::abs(r));
    }
    // converged: at the rounding level of T (a loose residual leaves the vector off by residual / gap, which
    // the weight floor − λ scales up); the last solve settles for a looser one
    if (res <= 2.0 * n * eps * tnorm || (it == 4 && res <= 64.0 * n * eps * tnorm)) {
      z_.col(c) = x_;
      return true;
    }
  }
  return false;
}

bool PartialEigenClip::compute(const Eigen::Ref<const Eigen::MatrixXd>& H, double floor, Eigen::MatrixXd& out) {
  const int n = static_cast<int>(H.rows());
  out = H.selfadjointView<Eigen::Lower>();
  k_ = 0;
  if (n == 0) return true;
  mat_ = H.triangularView<Eigen::Lower>();
  diag_.resize(n);
  sub_.resize(std::max(n - 1, 0));
  hcoeffs_.resize(std::max(n - 1, 0));
  Eigen::internal::tridiagonalization_inplace(mat_, diag_, sub_, hcoeffs_, false);
  vals_ = diag_;
  e2_.resize(n);
  e2_.head(n - 1) = sub_.cwiseAbs2();
  if (tqlrat(n, vals_.data(), e2_.data()) != 0 || !vals_.allFinite()) return false;
  while (k_ < n && vals_[k_] < floor) ++k_;
  if (k_ == 0) return true;
  const double tnorm = std::max(std::abs(vals_[0]), std::abs(vals_[n - 1]));
  const double eps = std::numeric_limits<double>::epsilon();
  z_.resize(n, k_);
  x_.resize(n);
  u0_.resize(n), u1_.resize(n), u2_.resize(n), l_.resize(n);
  piv_.assign(static_cast<std::size_t>(n), 0);
  mus_.assign(static_cast<std::size_t>(k_), 0.0);
  for (int c = 0; c < k_; ++c) {
    double mu = vals_[c];  // equal eigenvalues: shifts 10 ε ‖T‖ apart (as LAPACK's dstein)
    if (c > 0 && mu - mus_[static_cast<std::size_t>(c - 1)] < 10.0 * eps * tnorm)
      mu = mus_[static_cast<std::size_t>(c - 1)] + 10.0 * eps * tnorm;
    mus_[static_cast<std::size_t>(c)] = mu;
    if (!inverseIteration(c, mu, tnorm)) return false;
  }
  // back to H's coordinates: Q z with Q = H_0 ⋯ H_{n−2} the tridiagonalisation's reflectors (Eigen's storage:
  // H_i = I − τ_i v vᵀ on rows i+1.., v = [1, mat(i+2.., i)]), the last applied first (Eigen's
  // HouseholderSequence::applyThisOnTheLeft, written out: its per-reflector overhead dominates at n ≈ 20)
  for (int i = n - 2; i >= 0; --i) {
    const double tau = hcoeffs_[i];
    if (tau == 0.0) continue;
    const double* v = mat_.data() + static_cast<Eigen::Index>(i) * n;  // column i
    for (int c = 0; c < k_; ++c) {
      double* zc = z_.data() + static_cast<Eigen::Index>(c) * n;
      double s = zc[i + 1];
      for (int r = i + 2; r < n; ++r) s += v[r] * zc[r];
      s *= tau;
      zc[i + 1] -= s;
      for (int r = i + 2; r < n; ++r) zc[r] -= s * v[r];
    }
  }
  zw_ = z_;
  for (int c = 0; c < k_; ++c) zw_.col(c) *= floor - vals_[c];
  out.noalias() += zw_ * z_.transpose();
  return true;
}

}  // namespace lipmpcc::sqp
