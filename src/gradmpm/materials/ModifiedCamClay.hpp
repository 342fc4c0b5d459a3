#pragma once
// Modified Cam-Clay at finite strain (Roscoe & Burland 1968; Borja & Tamagnini 1998):
// hyperelasticity in the logarithmic elastic strain with a pressure-dependent bulk
// stiffness, the elliptic yield surface, and hardening by the plastic volume change,
// integrated by the exponential map in principal Kirchhoff space as the other laws
// (materials/PlasticLaw.hpp). Soil-mechanics signs inside the law: P = -tr(tau) / 3 and
// volumetric strains compression positive.
//   elasticity (Borja & Tamagnini's with alpha = 0: a stored energy, so the response is
//   path independent inside the surface):
//     P = p_0 exp(eps_v^e / kappa~),  q = 3 G eps_s^e,  kappa~ = kappa / (1 + e_0)
//   yield surface:  f = q^2 / M^2 + P (P - P_c) <= 0
//   hardening:      P_c = p_c0 exp(eps_v^p / (lambda~ - kappa~)),  lambda~ = lambda / (1 + e_0)
//   associated flow; the equivalent plastic strain state variable (eps_p) is eps_v^p.
// The points start at the isotropic effective stress p_0 (zero elastic strain) and the
// preconsolidation pressure p_c0 >= p_0: normally consolidated at p_c0 = p_0. In the
// e - ln p' plane the normal compression line has slope lambda and the swelling lines
// kappa (here as ln v - ln p, Butterfield's form, which the log strains make exact).
#include "gradmpm/materials/PlasticLaw.hpp"

namespace gradmpm {

struct CamClayParameters {
  double lambda = 0.0;        ///< slope of the normal compression line in e - ln p'
  double kappa = 0.0;         ///< slope of the swelling lines, < lambda
  double M = 0.0;             ///< the critical state line's slope q / p'
  double e0 = 0.0;            ///< the void ratio at the start
  double p0 = 0.0;            ///< the effective pressure at the start (> 0)
  double pc0 = 0.0;           ///< the preconsolidation pressure at the start (>= p0)
  double ocr = 1.0;           ///< started from a stress: P_c over the surface through it
  double shear_modulus = 0.0; ///< G (constant)
};

class ModifiedCamClay final : public PlasticLaw {
 public:
  ModifiedCamClay(const CamClayParameters& p, double rho);
  std::string model() const override { return "modified-cam-clay"; }
  /// The hardening by eps_v^p = int d_gamma df/dP is not associated with P_c (df/dP_c = -P):
  /// the consistent tangent is not symmetric (tests/test_cam_clay.cpp M2).
  bool symmetric_tangent() const override { return false; }
  void update(const Mat3& dF, const double* state_n, double* state, MaterialResponse& out) const override;
  void tangent(const MaterialResponse& r, int dim, Mat9& A) const override;
  double elastic_energy_density(const double* state) const override;
  /// The elastic strain of sigma (eps_v^e = kappa~ ln(P / p_0), e = s / 2G) and the
  /// plastic volume change that puts P_c at the overconsolidation ratio times the
  /// pressure where the surface through sigma meets q = 0: P + q^2 / (M^2 P).
  bool start_from_stress(const Mat3& sigma, double* state) const override;
  const CamClayParameters& parameters() const { return p_; }
  /// P(eps_v^e) and P_c(eps_v^p), compression positive.
  double pressure(double eps_v_elastic) const;
  double preconsolidation(double eps_v_plastic) const;
  double kappa_tilde() const { return kt_; }
  double lambda_tilde() const { return lt_; }

  /// G from Poisson's ratio at the initial bulk stiffness p_0 / kappa~.
  static double shear_modulus_of(double poisson, double p0, double kappa, double e0);

 private:
  const LinearStrength& law_strength() const override { return none_; }
  std::shared_ptr<PlasticLaw> clone() const override { return std::make_shared<ModifiedCamClay>(*this); }
  CamClayParameters p_;
  double kt_, lt_;  ///< kappa~, lambda~
  LinearStrength none_;
};

}  // namespace gradmpm
