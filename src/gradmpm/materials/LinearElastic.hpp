#pragma once
// Small-strain linear elasticity: sigma = D : eps with eps accumulated from sym(dF - I).
// State: the strain tensor (elastic_strain).
#include "gradmpm/materials/Material.hpp"

namespace gradmpm {

class LinearElastic final : public Material {
 public:
  LinearElastic(double young, double poisson, double rho);
  std::string model() const override { return "linear-elastic"; }
  bool finite_strain() const override { return false; }
  const std::vector<StateVariable>& state_variables() const override;
  void update(const Mat3& dF, const double* state_n, double* state, MaterialResponse& out) const override;
  void tangent(const MaterialResponse&, int, Mat9& A) const override { A = D_; }
  Mat3 elastic_strain(const double* state) const override;

 private:
  Mat9 D_;
};

}  // namespace gradmpm
