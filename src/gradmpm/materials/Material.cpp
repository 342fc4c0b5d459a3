#include "gradmpm/materials/Material.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace gradmpm {

namespace {
constexpr int at(int i, int j) { return 3 * i + j; }

Mat3 contract(const Mat9& D, const Mat3& e) {  // (D : e)_ij
  Mat3 s = Mat3::Zero();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l) s(i, j) += D(at(i, j), at(k, l)) * e(k, l);
  return s;
}

/// (ln a - ln b) / (a - b), the divided difference of ln, stable when a ~ b.
double log_divided_difference(double a, double b) {
  const double r = b / a - 1.0;
  if (std::abs(r) < 1e-6) return (1.0 - r / 2.0 + r * r / 3.0) / a;
  return std::log1p(r) / (a * r);
}
}  // namespace

Mat9 isotropic_elasticity(double young, double poisson) {
  const double lambda = young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson));
  const double mu = young / (2.0 * (1.0 + poisson));
  Mat9 D = Mat9::Zero();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l)
          D(at(i, j), at(k, l)) = lambda * (i == j) * (k == l) + mu * ((i == k) * (j == l) + (i == l) * (j == k));
  return D;
}

Mat3 Material::elastic_stress(const Mat3& eps) const {
  const double lambda = young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson));
  const double mu = young / (2.0 * (1.0 + poisson));
  return lambda * eps.trace() * Mat3::Identity() + 2.0 * mu * eps;
}

Mat3 Material::elastic_strain(const Mat3& s) const {
  return ((1.0 + poisson) * s - poisson * s.trace() * Mat3::Identity()) / young;
}

LinearElastic::LinearElastic(double E, double nu, double rho) : D_(isotropic_elasticity(E, nu)) {
  density = rho;
  young = E;
  poisson = nu;
}

void LinearElastic::update(const Mat3& dF, const Mat3& strain_n, MaterialResponse& out) const {
  const Mat3 g = dF - Mat3::Identity();
  out.strain = strain_n + 0.5 * (g + g.transpose());
  out.stress = contract(D_, out.strain);
}

Hencky::Hencky(double E, double nu, double rho)
    : D_(isotropic_elasticity(E, nu)), lambda_(E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))), mu_(E / (2.0 * (1.0 + nu))) {
  density = rho;
  young = E;
  poisson = nu;
}

void Hencky::update(const Mat3& dF, const Mat3& strain_n, MaterialResponse& out) const {
  // Trial elastic left Cauchy-Green tensor b_e = dF exp(2 eps_n) dF^T.
  Eigen::SelfAdjointEigenSolver<Mat3> eps_eig(strain_n);
  const Mat3 be_n =
      eps_eig.eigenvectors() * (2.0 * eps_eig.eigenvalues()).array().exp().matrix().asDiagonal() *
      eps_eig.eigenvectors().transpose();
  const Mat3 be = dF * be_n * dF.transpose();

  Eigen::SelfAdjointEigenSolver<Mat3> eig(be);
  const Eigen::Vector3d lam = eig.eigenvalues();
  const Mat3& n = eig.eigenvectors();  // columns n_a
  out.strain = n * (0.5 * lam.array().log()).matrix().asDiagonal() * n.transpose();
  out.stress = lambda_ * out.strain.trace() * Mat3::Identity() + 2.0 * mu_ * out.strain;
  out.principal = lam;
  out.directions = n;
}

void Hencky::tangent(const MaterialResponse& r, int dim, Mat9& A) const {
  // A = 1/2 D : L : B - tau_il d_jk (L = d ln b / d b, B = d b / d g), written in the
  // principal frame n_a of b, where L and B are diagonal and D stays isotropic. With
  // P_ab = n_a (x) n_b, theta_ab the divided difference of ln and tau_a = n_a.tau.n_a:
  //   A = lambda I(x)I + sum_a (2 mu - tau_a) P_aa P_aa
  //     + sum_{a<b} [mu theta_ab (l_b P_ab P_ab + l_a P_ba P_ba) + e_ab (P_ab P_ba + P_ba P_ab)],
  //   e_ab = mu theta_ab l_a - tau_a (= mu theta_ab l_b - tau_b: the major symmetry).
  // Nine rank-one terms instead of two dense 9x9 products (docs/performance.md).
  const Eigen::Vector3d& lam = r.principal;
  const Mat3& n = r.directions;
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
    W.col(a) = (2.0 * mu_ - tau[a]) * U.col(a);
  }
  int t = 3;
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b, t += 2) {
      const double theta = log_divided_difference(lam[a], lam[b]);
      const double e = mu_ * theta * lam[a] - tau[a];
      const auto pab = P(a, b), pba = P(b, a);
      U.col(t) = pab;
      W.col(t) = mu_ * theta * lam[b] * pab + e * pba;
      U.col(t + 1) = pba;
      W.col(t + 1) = mu_ * theta * lam[a] * pba + e * pab;
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
    for (int k = 0; k < dim; ++k) A(at(i, i), at(k, k)) += lambda_;
}

}  // namespace gradmpm
