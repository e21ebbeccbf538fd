// The eigenvalue clip of a symmetric matrix, H⁺ = V max(Λ, floor) Vᵀ, computed as H + Σ_{λ_i < floor}
// (floor − λ_i) v_i v_iᵀ: the Householder tridiagonalisation Qᵀ H Q = T (Eigen), all eigenvalues of T by the
// rational QL method (EISPACK's tqlrat: no square roots in its sweeps), the eigenvectors of the k eigenvalues
// below the floor only, by inverse iteration on T (LU with partial pivoting; clusters orthogonalised), carried
// back by Q. At n = 20 about two thirds of Eigen's SelfAdjointEigenSolver and rebuild V max(Λ, floor) Vᵀ, with
// the same H⁺ to rounding. When an eigenvalue does not converge or an inverse-iteration residual is too large,
// compute() returns false (the caller then uses the full eigendecomposition).
#pragma once

#include <Eigen/Core>
#include <vector>

namespace lipmpcc::sqp {

class PartialEigenClip {
 public:
  /// H⁺ of the symmetric ``H`` (n × n, its lower triangle read) into ``out`` (n × n, both triangles);
  /// false when the result cannot be trusted (``out`` then undefined).
  bool compute(const Eigen::Ref<const Eigen::MatrixXd>& H, double floor, Eigen::MatrixXd& out);
  /// Eigenvalues below the floor in the last compute().
  int below() const { return k_; }

 private:
  bool inverseIteration(int c, double mu, double tnorm);

  Eigen::MatrixXd mat_, z_, zw_;
  Eigen::VectorXd diag_, sub_, hcoeffs_, vals_, e2_, x_, u0_, u1_, u2_, l_, work_;
  std::vector<int> piv_;
  std::vector<double> mus_;
  int k_ = 0;
};

/// EISPACK's tqlrat: the eigenvalues of the symmetric tridiagonal matrix with diagonal ``d`` and squared
/// subdiagonal ``e2`` (e2[i] = T(i+1, i)², i < n − 1; e2 needs n entries and is destroyed) into ``d``, ascending.
/// Returns 0, or 1 + the index of an eigenvalue that did not converge in 30 iterations.
int tqlrat(int n, double* d, double* e2);

}  // namespace lipmpcc::sqp
