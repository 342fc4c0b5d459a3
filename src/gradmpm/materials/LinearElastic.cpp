#include "gradmpm/materials/LinearElastic.hpp"

#include "gradmpm/materials/MaterialRegistry.hpp"

namespace gradmpm {

LinearElastic::LinearElastic(double E, double nu, double rho)
    : ElasticStrainHistory(IsotropicElasticity(E, nu), rho, "small strain eps = sum of sym(dF - I)"),
      D_(elasticity().tensor()) {}

std::string LinearElastic::model() const { return "linear-elastic"; }

void LinearElastic::update(const Mat3& dF, const double* state_n, double* state, MaterialResponse& out) const {
  update_increment(dF - Mat3::Identity(), state_n, state, out);
}

void LinearElastic::update_increment(const Mat3& g, const double* state_n, double* state, MaterialResponse& out) const {
  const Mat3 eps = unpack_symmetric(state_n) + 0.5 * (g + g.transpose());
  out.stress = contract(D_, eps);
  pack_symmetric(eps, state);
}

MaterialInfo linear_elastic_info() {
  return elastic_law_info<LinearElastic>("linear-elastic", "small-strain linear elasticity");
}

}  // namespace gradmpm
