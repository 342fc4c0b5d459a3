#pragma once
// The base of laws whose whole history is the elastic strain tensor (Hencky, linear
// elasticity): one state variable, the symmetric tensor elastic_strain.
#include <string>
#include <vector>

#include "gradmpm/core/SymmetricTensor.hpp"
#include "gradmpm/materials/Material.hpp"

namespace gradmpm {

class ElasticStrainHistory : public Material {
 public:
  /// `doc`: what the strain is for this law (small, logarithmic, ...).
  ElasticStrainHistory(const IsotropicElasticity& e, double rho, std::string doc)
      : Material(e, rho), vars_{{"elastic_strain", StateVariable::Kind::SymmetricTensor, 0.0, std::move(doc)}} {}
  const std::vector<StateVariable>& state_variables() const override { return vars_; }
  Mat3 elastic_strain(const double* state) const override { return unpack_symmetric(state); }
  /// The elastic strain whose stress is sigma.
  bool start_from_stress(const Mat3& sigma, double* state) const override {
    pack_symmetric(elasticity().strain(sigma), state);
    return true;
  }

 private:
  std::vector<StateVariable> vars_;
};

}  // namespace gradmpm
