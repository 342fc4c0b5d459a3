#include "gradmpm/materials/Spectral.hpp"

#include <Eigen/Eigenvalues>
#include <array>
#include <cmath>

namespace gradmpm {

namespace {
constexpr int at(int i, int j) { return 3 * i + j; }
static_assert(MaterialResponse::cache_capacity >= 12);
}  // namespace

void symmetric_eigen(const Mat3& m, Eigen::Vector3d& values, Mat3& vectors) {
  if (m(2, 0) != 0.0 || m(2, 1) != 0.0) {
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(m);
    values = eig.eigenvalues();
    vectors = eig.eigenvectors();
    return;
  }
  // One Jacobi rotation J = [c s; -s c] diagonalises the block [a b; b d]: J^T B J =
  // diag(a - t b, d + t b), t = tan of the smaller rotation angle (Golub & Van Loan,
  // sym.schur2), accurate to round-off however close the eigenvalues are.
  const double a = m(0, 0), b = m(1, 0), d = m(1, 1);
  double t = 0.0;
  if (b != 0.0) {
    const double tau = (d - a) / (2.0 * b);
    t = (tau >= 0.0 ? 1.0 : -1.0) / (std::abs(tau) + std::sqrt(1.0 + tau * tau));
  }
  const double c = 1.0 / std::sqrt(1.0 + t * t), s = t * c;
  const std::array<double, 3> value{a - t * b, d + t * b, m(2, 2)};
  const std::array<Eigen::Vector3d, 3> vector{Eigen::Vector3d(c, -s, 0.0), Eigen::Vector3d(s, c, 0.0),
                                              Eigen::Vector3d(0.0, 0.0, 1.0)};
  std::array<int, 3> order{0, 1, 2};  // ascending, as Eigen's solver (MohrCoulomb relies on it)
  if (value[order[1]] < value[order[0]]) std::swap(order[0], order[1]);
  if (value[order[2]] < value[order[1]]) std::swap(order[1], order[2]);
  if (value[order[1]] < value[order[0]]) std::swap(order[0], order[1]);
  for (int k = 0; k < 3; ++k) {
    values[k] = value[order[k]];
    vectors.col(k) = vector[order[k]];
  }
}

ElasticTrial elastic_trial(const Mat3& dF, const Mat3& eps_n) {
  Eigen::Vector3d eps_values, l;
  Mat3 eps_vectors, n;
  symmetric_eigen(eps_n, eps_values, eps_vectors);
  const Mat3 be_n = eps_vectors * (2.0 * eps_values).array().exp().matrix().asDiagonal() * eps_vectors.transpose();
  symmetric_eigen(dF * be_n * dF.transpose(), l, n);
  return {l, n};
}

double log_divided_difference(double a, double b) {
  const double r = b / a - 1.0;
  if (std::abs(r) < 1e-6) return (1.0 - r / 2.0 + r * r / 3.0) / a;
  return std::log1p(r) / (a * r);
}

namespace {
/// The rank-one terms of the spectral tangent, A = iso I(x)I + U W^T, restricted to the R
/// rows `row` of the 9 (all of them in 3D, the in-plane ones, 3i + j with i, j < dim, in
/// 2D and 1D: the rest of A is not used there), so U and W are R x 9.
template <int R>
void spectral_terms(const ElasticTrial& trial, const Eigen::Vector3d& tau, const Mat3& D, const Eigen::Vector3d& spin,
                    const std::array<int, R>& row, Eigen::Matrix<double, R, 9>& U, Eigen::Matrix<double, R, 9>& W) {
  const Eigen::Vector3d& lam = trial.stretch2;
  const Mat3& n = trial.directions;
  using Column = Eigen::Matrix<double, R, 1>;
  auto P = [&](int a, int b) {  // the rows of vec(n_a (x) n_b), index 3i + j
    Column v;
    for (int r = 0; r < R; ++r) v[r] = n(row[r] / 3, a) * n(row[r] % 3, b);
    return v;
  };
  for (int a = 0; a < 3; ++a) U.col(a) = P(a, a);
  for (int a = 0; a < 3; ++a) {
    W.col(a) = (D(a, 0) - (a == 0 ? tau[a] : 0.0)) * U.col(0);
    for (int b = 1; b < 3; ++b) W.col(a) += (D(a, b) - (a == b ? tau[a] : 0.0)) * U.col(b);
  }
  int t = 3;
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b, t += 2) {
      const double c = spin[a + b - 1];  // (0,1) -> 0, (0,2) -> 1, (1,2) -> 2
      const double e = c * lam[a] - tau[a];
      const Column pab = P(a, b), pba = P(b, a);
      U.col(t) = pab;
      W.col(t) = c * lam[b] * pab + e * pba;
      U.col(t + 1) = pba;
      W.col(t + 1) = c * lam[a] * pba + e * pab;
    }
}

template <int R>
void restricted_tangent(const ElasticTrial& trial, const Eigen::Vector3d& tau, const Mat3& D,
                        const Eigen::Vector3d& spin, const std::array<int, R>& row, Mat9& A) {
  Eigen::Matrix<double, R, 9> U, W;
  spectral_terms<R>(trial, tau, D, spin, row, U, W);
  const Eigen::Matrix<double, R, R> block = U * W.transpose();
  A.setZero();
  for (int p = 0; p < R; ++p)
    for (int q = 0; q < R; ++q) A(row[p], row[q]) = block(p, q);
}
}  // namespace

void spectral_tangent(const ElasticTrial& trial, const Eigen::Vector3d& tau, double iso, const Mat3& D,
                      const Eigen::Vector3d& spin, int dim, Mat9& A) {
  // Nine rank-one terms instead of dense 9x9 products (docs/performance.md).
  if (dim == 3) {
    Eigen::Matrix<double, 9, 9> U, W;
    spectral_terms<9>(trial, tau, D, spin, {0, 1, 2, 3, 4, 5, 6, 7, 8}, U, W);
    A.noalias() = U.lazyProduct(W.transpose());
  } else if (dim == 2) {
    restricted_tangent<4>(trial, tau, D, spin, {at(0, 0), at(0, 1), at(1, 0), at(1, 1)}, A);
  } else {
    restricted_tangent<1>(trial, tau, D, spin, {at(0, 0)}, A);
  }
  for (int i = 0; i < dim; ++i)
    for (int k = 0; k < dim; ++k) A(at(i, i), at(k, k)) += iso;
}

Eigen::Vector3d principal_values(const Mat3& t, const ElasticTrial& trial) {
  Eigen::Vector3d v;
  for (int a = 0; a < 3; ++a) v[a] = trial.directions.col(a).dot(t * trial.directions.col(a));
  return v;
}

Eigen::Vector3d spin_coefficients(const ElasticTrial& trial, double scale) {
  const Eigen::Vector3d& l = trial.stretch2;
  return {scale * log_divided_difference(l[0], l[1]), scale * log_divided_difference(l[0], l[2]),
          scale * log_divided_difference(l[1], l[2])};
}

void store_trial(const ElasticTrial& t, MaterialResponse& r) {
  Eigen::Map<Eigen::Vector3d>(r.cache.data()) = t.stretch2;
  Eigen::Map<Mat3>(r.cache.data() + 3) = t.directions;
}

ElasticTrial load_trial(const MaterialResponse& r) {
  return {Eigen::Map<const Eigen::Vector3d>(r.cache.data()), Eigen::Map<const Mat3>(r.cache.data() + 3)};
}

}  // namespace gradmpm
