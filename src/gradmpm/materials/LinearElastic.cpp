#include "gradmpm/materials/LinearElastic.hpp"

#include "gradmpm/core/SymmetricTensor.hpp"
#include "gradmpm/materials/MaterialRegistry.hpp"

namespace gradmpm {

LinearElastic::LinearElastic(double E, double nu, double rho)
    : Material(IsotropicElasticity(E, nu), rho), D_(elasticity().tensor()) {}

const std::vector<StateVariable>& LinearElastic::state_variables() const {
  static const std::vector<StateVariable> vars = {
      {"elastic_strain", StateVariable::Kind::SymmetricTensor, 0.0, "small strain eps = sum of sym(dF - I)"}};
  return vars;
}

void LinearElastic::update(const Mat3& dF, const double* state_n, double* state, MaterialResponse& out) const {
  const Mat3 g = dF - Mat3::Identity();
  const Mat3 eps = unpack_symmetric(state_n) + 0.5 * (g + g.transpose());
  out.stress = contract(D_, eps);
  pack_symmetric(eps, state);
}

Mat3 LinearElastic::elastic_strain(const double* state) const { return unpack_symmetric(state); }

MaterialInfo linear_elastic_info() {
  return {"linear-elastic", "small-strain linear elasticity", isotropic_elasticity_keys(),
          [](const CaseFile& cf, const std::string& prefix, const MaterialInfo& self) {
            const ElasticSolid s = read_elastic_solid(cf, prefix, self);
            return std::make_shared<LinearElastic>(s.elasticity.young, s.elasticity.poisson, s.density);
          }};
}

}  // namespace gradmpm
