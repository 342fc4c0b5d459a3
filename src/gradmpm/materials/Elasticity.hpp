#pragma once
// Isotropic linear elasticity: the Lame constants computed once, sigma = D : eps, its
// inverse, and the 9x9 tensor D_ijkl (row i*3+j, column k*3+l). Used by the elastic
// laws, by the elastic predictor of plasticity, and by the gradient step, which pairs
// smoothed strains with stresses (gradient elasticity is a linear theory; with Hencky,
// eps is the logarithmic strain and the stress the Kirchhoff stress).
#include <Eigen/Core>

namespace gradmpm {

using Mat3 = Eigen::Matrix3d;
using Mat9 = Eigen::Matrix<double, 9, 9>;

struct IsotropicElasticity {
  double young = 0.0, poisson = 0.0;
  double lambda = 0.0, mu = 0.0;  ///< Lame constants

  IsotropicElasticity() = default;
  IsotropicElasticity(double E, double nu)
      : young(E), poisson(nu), lambda(E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))), mu(E / (2.0 * (1.0 + nu))) {}

  /// lambda tr(eps) I + 2 mu eps
  Mat3 stress(const Mat3& eps) const { return lambda * eps.trace() * Mat3::Identity() + 2.0 * mu * eps; }
  /// ((1 + nu) sigma - nu tr(sigma) I) / E
  Mat3 strain(const Mat3& s) const { return ((1.0 + poisson) * s - poisson * s.trace() * Mat3::Identity()) / young; }
  /// D_ijkl = lambda d_ij d_kl + mu (d_ik d_jl + d_il d_jk)
  Mat9 tensor() const;
};

/// (D : e)_ij = D_ijkl e_kl for a 9x9 fourth-order tensor.
Mat3 contract(const Mat9& D, const Mat3& e);

}  // namespace gradmpm
