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
  out.tangent = D_;
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

  // L_ijkl = sum_ab theta_ab n_ai n_bj n_ak n_bl (Daleckii-Krein derivative of ln).
  Mat3 theta;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) theta(a, b) = a == b ? 1.0 / lam[a] : log_divided_difference(lam[a], lam[b]);
  Mat9 L = Mat9::Zero();
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      Eigen::Matrix<double, 9, 1> m;  // (n_a (x) n_b) flattened
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) m[at(i, j)] = n(i, a) * n(j, b);
      L.noalias() += theta(a, b) * m * m.transpose();
    }
  Mat9 B = Mat9::Zero(), T = Mat9::Zero();
  for (int p = 0; p < 3; ++p)
    for (int q = 0; q < 3; ++q)
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l) {
          B(at(p, q), at(k, l)) = (p == k) * be(l, q) + (q == k) * be(p, l);
          T(at(p, q), at(k, l)) = out.stress(p, l) * (q == k);
        }
  out.tangent.noalias() = 0.5 * D_ * L * B;
  out.tangent -= T;
}

}  // namespace gradmpm
