// Cholesky factorisation and its uses for the small fixed sizes of the LM
// solver and the eskf (6x6), fully unrolled: Eigen's LDLT and LLT go through
// their general blocked kernels, which at these sizes cost more than the
// arithmetic. The reciprocals of the diagonal are kept, so the solves
// multiply instead of divide.
#pragma once

#include <Eigen/Core>
#include <cmath>

namespace earshot::tracker::detail {

/// A = L L^T, L lower triangular (its upper part is not used).
template <int N>
struct Cholesky {
  Eigen::Matrix<double, N, N> L;
  Eigen::Matrix<double, N, 1> inv_diag;  ///< 1 / L(i, i)
};

/// Factors a symmetric positive-definite A (only its lower triangle is
/// read). False when A is not positive definite to working precision.
template <int N>
bool cholesky(const Eigen::Matrix<double, N, N>& A, Cholesky<N>& f) {
  auto& L = f.L;
#pragma GCC unroll 8
  for (int j = 0; j < N; ++j) {
    double d = A(j, j);
#pragma GCC unroll 8
    for (int k = 0; k < j; ++k) d -= L(j, k) * L(j, k);
    if (!(d > 0.0)) return false;
    const double ljj = std::sqrt(d);
    const double inv = 1.0 / ljj;
    L(j, j) = ljj;
    f.inv_diag(j) = inv;
#pragma GCC unroll 8
    for (int i = j + 1; i < N; ++i) {
      double v = A(i, j);
#pragma GCC unroll 8
      for (int k = 0; k < j; ++k) v -= L(i, k) * L(j, k);
      L(i, j) = v * inv;
    }
  }
  return true;
}

/// y = L^-1 b (forward substitution).
template <int N>
Eigen::Matrix<double, N, 1> forward_solve(const Cholesky<N>& f, const Eigen::Matrix<double, N, 1>& b) {
  Eigen::Matrix<double, N, 1> y;
#pragma GCC unroll 8
  for (int i = 0; i < N; ++i) {
    double v = b(i);
#pragma GCC unroll 8
    for (int k = 0; k < i; ++k) v -= f.L(i, k) * y(k);
    y(i) = v * f.inv_diag(i);
  }
  return y;
}

/// x = L^-T y (back substitution).
template <int N>
Eigen::Matrix<double, N, 1> back_solve(const Cholesky<N>& f, const Eigen::Matrix<double, N, 1>& y) {
  Eigen::Matrix<double, N, 1> x;
#pragma GCC unroll 8
  for (int i = N - 1; i >= 0; --i) {
    double v = y(i);
#pragma GCC unroll 8
    for (int k = i + 1; k < N; ++k) v -= f.L(k, i) * x(k);
    x(i) = v * f.inv_diag(i);
  }
  return x;
}

/// A^-1 b.
template <int N>
Eigen::Matrix<double, N, 1> cholesky_solve(const Cholesky<N>& f, const Eigen::Matrix<double, N, 1>& b) {
  return back_solve<N>(f, forward_solve<N>(f, b));
}

/// A^-1: M = L^-1, A^-1 = M^T M.
template <int N>
Eigen::Matrix<double, N, N> inverse(const Cholesky<N>& f) {
  Eigen::Matrix<double, N, N> M = Eigen::Matrix<double, N, N>::Zero(), inv;
#pragma GCC unroll 8
  for (int j = 0; j < N; ++j) {
    M(j, j) = f.inv_diag(j);
#pragma GCC unroll 8
    for (int i = j + 1; i < N; ++i) {
      double v = 0.0;
#pragma GCC unroll 8
      for (int k = j; k < i; ++k) v -= f.L(i, k) * M(k, j);
      M(i, j) = v * f.inv_diag(i);
    }
  }
#pragma GCC unroll 8
  for (int i = 0; i < N; ++i)
#pragma GCC unroll 8
    for (int j = 0; j <= i; ++j) {
      double v = 0.0;
#pragma GCC unroll 8
      for (int k = i; k < N; ++k) v += M(k, i) * M(k, j);
      inv(i, j) = inv(j, i) = v;
    }
  return inv;
}

/// x^T A^-1 x.
template <int N>
double mahalanobis2(const Cholesky<N>& f, const Eigen::Matrix<double, N, 1>& x) {
  return forward_solve<N>(f, x).squaredNorm();
}

}  // namespace earshot::tracker::detail
