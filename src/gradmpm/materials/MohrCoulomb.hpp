#pragma once
// Finite-strain Mohr-Coulomb elasto-plasticity, perfectly plastic, non-associated:
//   f = k sigma_1 - sigma_3 - sigma_c,  k = (1 + sin phi) / (1 - sin phi),
//   sigma_c = 2 c cos phi / (1 - sin phi),  potential m sigma_1 - sigma_3 (m from psi),
// with sigma_1 >= sigma_2 >= sigma_3 the principal Kirchhoff stresses (tension positive).
// Hencky elasticity and the exponential map as in materials/VonMises.hpp; the return in
// principal space goes to the plane, to either edge (sigma_1 = sigma_2 or sigma_2 =
// sigma_3) or to the apex (Clausen, Damkilde & Andersen 2006, 2007): each is a linear map
// of the trial stress, and its derivative is the algorithmic tangent. psi < phi gives a
// non-symmetric tangent, solved as such. eps_p accumulates sqrt(2/3) |d_eps_p|.
// Not yet: softening of the cohesion, a tension cut-off (issue 10).
#include "gradmpm/materials/PlasticLaw.hpp"

namespace gradmpm {

struct MohrCoulombParameters {
  double cohesion = 0.0;        ///< c > 0
  double friction_angle = 0.0;  ///< phi, degrees, > 0
  double dilation_angle = 0.0;  ///< psi, degrees, <= phi
};

class MohrCoulomb final : public PlasticLaw {
 public:
  enum class Region { Elastic, Plane, EdgeCompression, EdgeExtension, Apex };
  MohrCoulomb(const IsotropicElasticity& e, double rho, const MohrCoulombParameters& p);
  std::string model() const override { return "mohr-coulomb"; }
  bool symmetric_tangent() const override { return k_ == m_; }
  void update(const Mat3& dF, const double* state_n, double* state, MaterialResponse& out) const override;
  void tangent(const MaterialResponse& r, int dim, Mat9& A) const override;
  /// Which return the last update took (from its response).
  static Region region(const MaterialResponse& r);
  /// f at principal stresses sorted descending.
  double yield(const Eigen::Vector3d& sorted) const { return k_ * sorted[0] - sorted[2] - sigma_c_; }

 private:
  /// The return of a sorted trial stress: the stress and d sigma / d sigma_trial.
  Region return_map(const Eigen::Vector3d& trial, Eigen::Vector3d& sigma, Mat3& dsigma) const;
  double k_, m_, sigma_c_;
  Mat3 D_;  ///< principal elasticity lambda 1(x)1 + 2 mu I
};

}  // namespace gradmpm
