#include "gradmpm/materials/Hencky.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "gradmpm/materials/MaterialRegistry.hpp"

namespace gradmpm {

namespace {
constexpr int at(int i, int j) { return 3 * i + j; }

/// (ln a - ln b) / (a - b), the divided difference of ln, stable when a ~ b.
double log_divided_difference(double a, double b) {
  const double r = b / a - 1.0;
  if (std::abs(r) < 1e-6) return (1.0 - r / 2.0 + r * r / 3.0) / a;
  return std::log1p(r) / (a * r);
}

// The tangent cache: principal values of the trial b_e (3), then their directions
// (columns, 9).
static_assert(MaterialResponse::cache_capacity >= 12);
using PrincipalValues = Eigen::Map<Eigen::Vector3d>;
using PrincipalDirections = Eigen::Map<Mat3>;
}  // namespace

Hencky::Hencky(double E, double nu, double rho)
    : ElasticStrainHistory(IsotropicElasticity(E, nu), rho, "logarithmic elastic strain eps_e = 1/2 ln b_e") {}

void Hencky::update(const Mat3& dF, const double* state_n, double* state, MaterialResponse& out) const {
  // Trial elastic left Cauchy-Green tensor b_e = dF exp(2 eps_n) dF^T.
  Eigen::SelfAdjointEigenSolver<Mat3> eps_eig(unpack_symmetric(state_n));
  const Mat3 be_n = eps_eig.eigenvectors() * (2.0 * eps_eig.eigenvalues()).array().exp().matrix().asDiagonal() *
                    eps_eig.eigenvectors().transpose();
  const Mat3 be = dF * be_n * dF.transpose();

  Eigen::SelfAdjointEigenSolver<Mat3> eig(be);
  const Eigen::Vector3d lam = eig.eigenvalues();
  const Mat3& n = eig.eigenvectors();  // columns n_a
  const Mat3 eps = n * (0.5 * lam.array().log()).matrix().asDiagonal() * n.transpose();
  const IsotropicElasticity& e = elasticity();
  out.stress = e.lambda * eps.trace() * Mat3::Identity() + 2.0 * e.mu * eps;
  pack_symmetric(eps, state);
  PrincipalValues(out.cache.data()) = lam;
  PrincipalDirections(out.cache.data() + 3) = n;
}

void Hencky::tangent(const MaterialResponse& r, int dim, Mat9& A) const {
  // A = 1/2 D : L : B - tau_il d_jk (L = d ln b / d b, B = d b / d g), written in the
  // principal frame n_a of b, where L and B are diagonal and D stays isotropic. With
  // P_ab = n_a (x) n_b, theta_ab the divided difference of ln and tau_a = n_a.tau.n_a:
  //   A = lambda I(x)I + sum_a (2 mu - tau_a) P_aa P_aa
  //     + sum_{a<b} [mu theta_ab (l_b P_ab P_ab + l_a P_ba P_ba) + e_ab (P_ab P_ba + P_ba P_ab)],
  //   e_ab = mu theta_ab l_a - tau_a (= mu theta_ab l_b - tau_b: the major symmetry).
  // Nine rank-one terms instead of two dense 9x9 products (docs/performance.md).
  const Eigen::Vector3d lam = Eigen::Map<const Eigen::Vector3d>(r.cache.data());
  const Mat3 n = Eigen::Map<const Mat3>(r.cache.data() + 3);
  const double mu = elasticity().mu, lambda = elasticity().lambda;
  auto P = [&](int a, int b) {  // vec(n_a (x) n_b), index 3i + j
    Eigen::Matrix<double, 9, 1> v;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) v[at(i, j)] = n(i, a) * n(j, b);
    return v;
  };
  Eigen::Vector3d tau;  // principal Kirchhoff stresses
  for (int a = 0; a < 3; ++a) tau[a] = n.col(a).dot(r.stress * n.col(a));
  Mat9 U, W;  // A = lambda I(x)I + U W^T, column t of U and W one rank-one term
  for (int a = 0; a < 3; ++a) {
    U.col(a) = P(a, a);
    W.col(a) = (2.0 * mu - tau[a]) * U.col(a);
  }
  int t = 3;
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b, t += 2) {
      const double theta = log_divided_difference(lam[a], lam[b]);
      const double e = mu * theta * lam[a] - tau[a];
      const auto pab = P(a, b), pba = P(b, a);
      U.col(t) = pab;
      W.col(t) = mu * theta * lam[b] * pab + e * pba;
      U.col(t + 1) = pba;
      W.col(t + 1) = mu * theta * lam[a] * pba + e * pab;
    }
  if (dim == 3) {
    A.noalias() = U.lazyProduct(W.transpose());
  } else {  // the in-plane block only: dim^4 of the 81 entries
    A.setZero();
    for (int i = 0; i < dim; ++i)
      for (int j = 0; j < dim; ++j)
        for (int k = 0; k < dim; ++k)
          for (int l = 0; l < dim; ++l) A(at(i, j), at(k, l)) = U.row(at(i, j)).dot(W.row(at(k, l)));
  }
  for (int i = 0; i < dim; ++i)
    for (int k = 0; k < dim; ++k) A(at(i, i), at(k, k)) += lambda;
}

MaterialInfo hencky_info() {
  return elastic_law_info<Hencky>("hencky", "Hencky (logarithmic-strain) hyperelasticity, finite strain");
}

}  // namespace gradmpm
