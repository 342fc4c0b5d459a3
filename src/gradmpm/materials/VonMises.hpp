#pragma once
// Finite-strain von Mises (J2) elasto-plasticity with linear isotropic hardening or
// softening of the yield stress on the equivalent plastic strain kappa = int sqrt(2/3)|d eps_p|,
// down to a residual yield stress. Multiplicative split, Hencky elasticity, return mapping
// by backward Euler in principal logarithmic-strain / Kirchhoff-stress space (the radial
// return carried to finite strain by the exponential map, Simo 1992; AMPLE's VMconst.m):
//   eps_tr = 1/2 ln b_e,trial (principal), tau_tr = D : eps_tr, q_tr = sqrt(3/2) |dev tau_tr|
//   f = q_tr - sigma_y(kappa_n) <= 0: elastic; else
//   d_gamma = f / (3 mu + H), s = (1 - 3 mu d_gamma / q_tr) dev tau_tr,
//   eps_e = eps_tr - d_gamma 3/2 dev tau_tr / q_tr, kappa = kappa_n + d_gamma.
// The algorithmic tangent in principal space, D = K 1(x)1 + 2 mu beta I_dev +
// 2 mu (1 - beta - 3 mu / (3 mu + H)) N(x)N (beta = 1 - 3 mu d_gamma / q_tr, N = s / |s|),
// enters the spectral tangent of materials/Spectral.hpp with spin terms mu beta theta_ab:
// Newton converges quadratically in plastic steps. Associated flow: symmetric tangent.
// State: elastic_strain (eps_e), eps_p (kappa).
#include "gradmpm/materials/PlasticLaw.hpp"

namespace gradmpm {

struct VonMisesParameters {
  double yield_stress = 0.0;           ///< sigma_y0, uniaxial, > 0
  double hardening = 0.0;              ///< H = d sigma_y / d kappa; < 0 softens
  double residual_yield_stress = 0.0;  ///< the floor softening stops at
};

class VonMises final : public PlasticLaw {
 public:
  VonMises(const IsotropicElasticity& e, double rho, const VonMisesParameters& p);
  std::string model() const override { return "von-mises"; }
  void update(const Mat3& dF, const double* state_n, double* state, MaterialResponse& out) const override;
  void tangent(const MaterialResponse& r, int dim, Mat9& A) const override;
  /// sigma_y(kappa), and whether the residual floor holds it.
  double yield_stress(double kappa, bool* at_floor = nullptr) const { return yield_.at(kappa, at_floor); }

 private:
  const LinearStrength& law_strength() const override { return yield_; }
  std::shared_ptr<PlasticLaw> clone() const override { return std::make_shared<VonMises>(*this); }
  std::shared_ptr<PlasticLaw> strength_divided(double F) const override {
    return std::make_shared<VonMises>(elasticity(), density(),
                                      VonMisesParameters{params_.yield_stress / F, params_.hardening / F,
                                                         params_.residual_yield_stress / F});
  }
  VonMisesParameters params_;
  LinearStrength yield_;
};

}  // namespace gradmpm
