#include "gradmpm/materials/Hencky.hpp"

#include "gradmpm/materials/MaterialRegistry.hpp"
#include "gradmpm/materials/Spectral.hpp"

namespace gradmpm {

Hencky::Hencky(double E, double nu, double rho)
    : ElasticStrainHistory(IsotropicElasticity(E, nu), rho, "logarithmic elastic strain eps_e = 1/2 ln b_e") {}

void Hencky::update(const Mat3& dF, const double* state_n, double* state, MaterialResponse& out) const {
  const ElasticTrial trial = elastic_trial(dF, unpack_symmetric(state_n));
  const Mat3& n = trial.directions;
  const Mat3 eps = n * trial.log_strain().asDiagonal() * n.transpose();
  const IsotropicElasticity& e = elasticity();
  out.stress = e.lambda * eps.trace() * Mat3::Identity() + 2.0 * e.mu * eps;
  pack_symmetric(eps, state);
  store_trial(trial, out);
}

void Hencky::tangent(const MaterialResponse& r, int dim, Mat9& A) const {
  // Spectral form (materials/Spectral.hpp) with D_ab = lambda + 2 mu d_ab (lambda kept
  // apart) and c_ab = mu theta_ab, theta the divided difference of ln (tau_a - tau_b =
  // mu (ln l_a - ln l_b)).
  const ElasticTrial trial = load_trial(r);
  const double mu = elasticity().mu;
  spectral_tangent(trial, principal_values(r.stress, trial), elasticity().lambda, 2.0 * mu * Mat3::Identity(),
                   spin_coefficients(trial, mu), dim, A);
}

MaterialInfo hencky_info() {
  return elastic_law_info<Hencky>("hencky", "Hencky (logarithmic-strain) hyperelasticity, finite strain");
}

}  // namespace gradmpm
