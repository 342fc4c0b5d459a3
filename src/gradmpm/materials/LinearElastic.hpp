#pragma once
// Small-strain linear elasticity: sigma = D : eps with eps accumulated from sym(dF - I).
// State: the strain tensor (elastic_strain).
#include "gradmpm/materials/ElasticStrainHistory.hpp"

namespace gradmpm {

class LinearElastic final : public ElasticStrainHistory {
 public:
  LinearElastic(double young, double poisson, double rho);
  std::string model() const override;
  bool finite_strain() const override { return false; }
  /// The tangent is D at every state.
  void tangent(const MaterialResponse&, int, Mat9& A) const override { A = D_; }
  void update(const Mat3& dF, const double* state_n, double* state, MaterialResponse& out) const override;
  void update_increment(const Mat3& g, const double* state_n, double* state, MaterialResponse& out) const override;

 private:
  Mat9 D_;
};

}  // namespace gradmpm
