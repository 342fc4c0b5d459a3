#pragma once
// Hencky (logarithmic-strain) hyperelasticity: tau = D : eps_e, eps_e = 1/2 ln b_e,
// b_e = dF exp(2 eps_e,n) dF^T, sigma = tau / det F. The consistent tangent is
// A = 1/2 D : L : B - tau_il d_jk with L = d ln(b)/d b and B_pqkl = d_pk b_lq + d_qk b_pl.
// State: the logarithmic elastic strain eps_e (elastic_strain).
#include "gradmpm/materials/ElasticStrainHistory.hpp"

namespace gradmpm {

class Hencky final : public ElasticStrainHistory {
 public:
  Hencky(double young, double poisson, double rho);
  std::string model() const override { return "hencky"; }
  bool finite_strain() const override { return true; }
  void update(const Mat3& dF, const double* state_n, double* state, MaterialResponse& out) const override;
  void tangent(const MaterialResponse& r, int dim, Mat9& A) const override;
};

}  // namespace gradmpm
