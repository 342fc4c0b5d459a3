#pragma once
// Finite-strain Mohr-Coulomb elasto-plasticity, non-associated, with a softening (or
// hardening) cohesion and an optional tension cut-off:
//   f = k sigma_1 - sigma_3 - sigma_c(kappa),  k = (1 + sin phi) / (1 - sin phi),
//   sigma_c = 2 c(kappa) cos phi / (1 - sin phi),  potential m sigma_1 - sigma_3 (m from psi),
//   c(kappa) = max(residual_cohesion, cohesion + hardening kappa) (linear; no floor when H > 0),
//   t = sigma_1 - sigma_t <= 0 (Rankine cut-off, associated),
// with sigma_1 >= sigma_2 >= sigma_3 the principal Kirchhoff stresses (tension positive).
// Hencky elasticity and the exponential map as in materials/VonMises.hpp. The return in
// principal space goes to the plane, to either edge (sigma_1 = sigma_2 or sigma_2 =
// sigma_3), to the apex (Clausen, Damkilde & Andersen 2006, 2007) or to the cut-off's
// plane, edges and apex: in sorted principal space every one of these is the closest
// point (in the energy norm, along the flow directions) of a set of active planes, so the
// return tries the active sets by size and takes the first that satisfies the
// Kuhn-Tucker conditions. For a fixed strength each is a linear map of the trial stress;
// softening adds one scalar equation, sigma_c = sigma_c(kappa(sigma_c)), solved by Newton.
// The derivative of the whole is the algorithmic tangent; psi < phi gives a non-symmetric
// tangent, solved as such. eps_p accumulates kappa = int sqrt(2/3) |d eps_p|.
#include <array>
#include <limits>

#include "gradmpm/materials/PlasticLaw.hpp"

namespace gradmpm {

struct MohrCoulombParameters {
  double cohesion = 0.0;                                            ///< c > 0
  double friction_angle = 0.0;                                      ///< phi, degrees, > 0
  double dilation_angle = 0.0;                                      ///< psi, degrees, <= phi
  double hardening = 0.0;                                           ///< H = dc / d kappa; negative: softening
  double residual_cohesion = 0.0;                                   ///< the floor of softening
  double tension_cutoff = std::numeric_limits<double>::infinity();  ///< sigma_t >= 0; infinite: none
};

class MohrCoulomb final : public PlasticLaw {
 public:
  enum class Region { Elastic, Plane, EdgeCompression, EdgeExtension, Apex, Tension };
  MohrCoulomb(const IsotropicElasticity& e, double rho, const MohrCoulombParameters& p);
  std::string model() const override { return "mohr-coulomb"; }
  bool symmetric_tangent() const override { return k_ == m_; }
  void update(const Mat3& dF, const double* state_n, double* state, MaterialResponse& out) const override;
  void tangent(const MaterialResponse& r, int dim, Mat9& A) const override;
  /// Which return the last update took (from its response); Tension: any return that
  /// involves the cut-off.
  static Region region(const MaterialResponse& r);
  /// f at principal stresses sorted descending, at the strength of kappa.
  double yield(const Eigen::Vector3d& sorted, double kappa = 0.0) const {
    return k_ * sorted[0] - sorted[2] - strength(kappa);
  }
  /// sigma_c at kappa.
  double strength(double kappa) const { return 2.0 * std::sqrt(k_) * cohesion_.at(kappa); }
  double tension_cutoff() const { return sigma_t_; }

  /// The return of a sorted trial stress at the strength sigma_c = s: the stress, its
  /// derivatives d sigma / d trial (P) and d sigma / d s (g), and the active planes
  /// (bits 0-5: Mohr-Coulomb's planes k sigma_i - sigma_j, the main one first; 6-8: the
  /// cut-off's sigma_i = sigma_t).
  struct Return {
    unsigned active = 0;
    Eigen::Vector3d sigma;
    Mat3 P;
    Eigen::Vector3d g;
  };
  Return return_map(const Eigen::Vector3d& trial, double s) const;
  /// The same return when the active set is known (`active`, from an earlier return of
  /// this trial at this strength, as the tangent has it): no search over the sets.
  Return return_map(const Eigen::Vector3d& trial, double s, unsigned active) const;

 private:
  /// The closest point on the planes of `set` (into `out`); false when they cannot hold
  /// the stress (dependent planes, a negative multiplier, another plane violated).
  bool return_onto(unsigned set, const Eigen::Vector3d& trial, double s, Return& out) const;
  /// Beyond the apex, where no set holds the stress.
  Return beyond_apex(double s) const;

  const LinearStrength& law_strength() const override { return cohesion_; }
  std::shared_ptr<PlasticLaw> clone() const override { return std::make_shared<MohrCoulomb>(*this); }
  std::shared_ptr<PlasticLaw> strength_divided(double F) const override;

  MohrCoulombParameters params_;

  double k_, m_, sigma_t_;
  std::array<Eigen::Vector3d, 9> a_, b_;  ///< the planes' normals and flow directions
  LinearStrength cohesion_;
  Mat3 D_, D_inv_;  ///< principal elasticity lambda 1(x)1 + 2 mu I and its inverse
};

}  // namespace gradmpm
