#pragma once
// Finite-strain Drucker-Prager elasto-plasticity, non-associated, with linear hardening
// or softening of the cohesion on the equivalent plastic strain down to a residual
// cohesion. Hencky elasticity; return mapping in principal logarithmic-strain / Kirchhoff
// space by the exponential map (as materials/VonMises.hpp), to the smooth cone or to its
// apex (de Souza Neto, Peric & Owen 2008, Boxes 8.9-8.10):
//   Phi = sqrt(J2(s)) + eta p - xi c(kappa),   flow potential sqrt(J2) + eta_bar p,
//   p = tr(tau)/3 (tension positive), kappa = int xi d_gamma.
// The cone is fitted to Mohr-Coulomb's friction and dilation angles: "plane-strain"
// (the collapse loads of Mohr-Coulomb in plane strain), "outer" (compressive meridian)
// or "inner" (tensile meridian). dilation_angle < friction_angle gives a non-symmetric
// tangent, solved as such ([linear_solver] general).
// State: elastic_strain (eps_e), eps_p (kappa).
#include <string>

#include "gradmpm/materials/PlasticLaw.hpp"

namespace gradmpm {

struct DruckerPragerParameters {
  double cohesion = 0.0;             ///< c0 > 0
  double friction_angle = 0.0;       ///< phi, degrees
  double dilation_angle = 0.0;       ///< psi, degrees, <= phi
  std::string fit = "plane-strain";  ///< "plane-strain", "outer" or "inner"
  double hardening = 0.0;            ///< H = dc / d kappa; < 0 softens
  double residual_cohesion = 0.0;    ///< the floor softening stops at
};

class DruckerPrager final : public PlasticLaw {
 public:
  DruckerPrager(const IsotropicElasticity& e, double rho, const DruckerPragerParameters& p);
  std::string model() const override { return "drucker-prager"; }
  bool symmetric_tangent() const override { return eta_ == eta_bar_; }
  void update(const Mat3& dF, const double* state_n, double* state, MaterialResponse& out) const override;
  void tangent(const MaterialResponse& r, int dim, Mat9& A) const override;
  /// c(kappa), and whether the residual floor holds it.
  double cohesion(double kappa, bool* at_floor = nullptr) const { return cohesion_.at(kappa, at_floor); }
  /// The cone: sqrt(J2) + eta p - xi c <= 0, potential slope eta_bar.
  double eta() const { return eta_; }
  double xi() const { return xi_; }
  double eta_bar() const { return eta_bar_; }

 private:
  const LinearStrength& law_strength() const override { return cohesion_; }
  std::shared_ptr<PlasticLaw> clone() const override { return std::make_shared<DruckerPrager>(*this); }
  std::shared_ptr<PlasticLaw> strength_divided(double F) const override;
  DruckerPragerParameters params_;
  LinearStrength cohesion_;
  double eta_, xi_, eta_bar_;
};

}  // namespace gradmpm
