#pragma once
// The constitutive interface of the implicit MPM (the pattern of geomechanics/mpm's
// Material and deal.II step-44's material classes). A material answers, for one point
// and one Newton iterate, "given the deformation-gradient increment dF of this load step
// and the history at the start of the step, what are the stress and the new history?"
// (update), and "what is the consistent tangent at that state?" (tangent). The two are
// separate because Newton needs the tangent only when the residual has not converged,
// and the global assembly forms it point by point without storing it.
//
// History is the material's own: it declares its state variables (names, kinds,
// initial values); the points keep every point's state in one flat block
// (MaterialPoints::state) and the driver copies the trial state in on convergence, so
// neither the points nor the driver know what a law stores. Every state variable reaches
// the VTU files and points_final.csv by name.
//
// Tensors are 3x3 in every dimension (plane strain and 1D uniaxial strain embed their
// dim x dim blocks); fourth-order tensors are 9x9 with row i*3+j and column k*3+l.
//
// Recipe "add a material" (docs/architecture.md): one header and source under
// materials/ with a class derived from Material and a MaterialInfo (model name, keys,
// make), plus one registration line in MaterialRegistry.cpp; tests/test_materials.cpp
// registers a toy law defined only in the test the same way.
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "gradmpm/materials/Elasticity.hpp"

namespace gradmpm {

/// One named piece of a material's history.
struct StateVariable {
  enum class Kind { Scalar, SymmetricTensor };
  std::string name;  ///< as written in outputs: VTU array name; CSV column (tensors: name_xx, ...)
  Kind kind = Kind::Scalar;
  double initial = 0.0;  ///< initial value (of every component)
  std::string doc;
  int size() const { return kind == Kind::Scalar ? 1 : 6; }
};

/// What update() leaves for the caller and for tangent().
struct MaterialResponse {
  static constexpr int cache_capacity = 16;
  Mat3 stress;  ///< Kirchhoff tau (finite strain) or Cauchy sigma (small strain)
  /// Whatever the material's tangent() needs from its update(), e.g. principal stretches
  /// and directions. Fixed capacity: no allocation per point.
  std::array<double, cache_capacity> cache;
};

class Material {
 public:
  Material(const IsotropicElasticity& e, double rho) : elasticity_(e), density_(rho) {}
  virtual ~Material() = default;

  /// The registry's model name ("hencky", ...).
  virtual std::string model() const = 0;
  /// true: updated-Lagrangian finite strain (stress is Kirchhoff, gradients are taken in
  /// the current configuration); false: incremental small strain on the configuration at
  /// the start of the load step.
  virtual bool finite_strain() const = 0;
  /// false: the consistent tangent is not symmetric (e.g. non-associated flow); the
  /// global tangent is then solved by a general solver, never symmetrised.
  virtual bool symmetric_tangent() const { return true; }
  /// The state variables, in the order of the state block.
  virtual const std::vector<StateVariable>& state_variables() const = 0;

  /// `dF`: deformation gradient of the step's displacement increment, I + d(du)/dx_n.
  /// `state_n`: the history at the start of the step (state_size() values); `state`:
  /// where the new history goes. Fills `out` for tangent().
  virtual void update(const Mat3& dF, const double* state_n, double* state, MaterialResponse& out) const = 0;
  /// update() from the increment's displacement gradient g = dF - I, as the driver has it.
  /// Small-strain laws use g as it is: forming I + g first rounds a strain of 1e-8 to
  /// 8 digits, and Newton's relative residual then floors at 1e-16 / |g|.
  virtual void update_increment(const Mat3& g, const double* state_n, double* state, MaterialResponse& out) const {
    update(Mat3::Identity() + g, state_n, state, out);
  }
  /// The consistent tangent at the state `r` that update() returned:
  /// A_ijkl with d(stress_ij grad_j eta_i) = grad_j eta_i A_ijkl grad_l du_k.
  /// Entries with every index below `dim` are computed (plane strain and 1D need no
  /// more); a material may leave the others zero. dim = 3 gives the whole tensor.
  virtual void tangent(const MaterialResponse& r, int dim, Mat9& A) const = 0;
  /// The elastic strain held in a state (logarithmic for finite strain): the field the
  /// gradient step smooths for e-RA and the VTU files' elastic_strain.
  virtual Mat3 elastic_strain(const double* state) const = 0;

  /// The elastic energy per unit volume stored in a state (finite strain: per reference
  /// volume, Hencky's 1/2 eps_e : D : eps_e). What a point has dissipated is its stress's
  /// work less this (MaterialPoints::work); a law with other elasticity overrides it.
  virtual double elastic_energy_density(const double* state) const {
    const Mat3 e = elastic_strain(state);
    return 0.5 * elasticity_.lambda * e.trace() * e.trace() + elasticity_.mu * e.squaredNorm();
  }

  /// The isotropic elasticity; the gradient step pairs smoothed strains with stresses by it.
  const IsotropicElasticity& elasticity() const { return elasticity_; }
  double density() const { return density_; }  ///< reference mass density rho_0

  /// Whether the strength falls with plastic strain (what [regularisation] acts on).
  virtual bool softens() const { return false; }
  /// This law with the implicit-gradient regularisation of weight m (docs/shear-bands.md),
  /// or null when the law has none.
  virtual std::shared_ptr<const Material> regularised(double /*m*/) const { return nullptr; }

  int state_size() const;
  /// Writes the initial values of every state variable.
  void initial_state(double* state) const;
  /// Whether the law has a strength (yields); elastic laws have none.
  virtual bool has_strength() const { return false; }
  /// This law with its strength divided by the factor F of a strength-reduction analysis
  /// (app/StrengthReduction.hpp): c / F with tan(phi) / F and tan(psi) / F (Mohr-Coulomb,
  /// Drucker-Prager), sigma_y / F (von Mises), hardening and residual values with them;
  /// null when the law has no strength, or one it cannot reduce (Modified Cam-Clay).
  virtual std::shared_ptr<const Material> strength_reduced(double /*F*/) const { return nullptr; }
  /// Writes the state of a point at rest under the stress `sigma` (F = I, so Cauchy and
  /// Kirchhoff agree): an initial (geostatic) stress, mpm/InitialStress.hpp. Returns false
  /// when the law cannot start from a stress. The state need not be admissible: the caller
  /// checks the stress against the law's surface by an update at dF = I.
  virtual bool start_from_stress(const Mat3& /*sigma*/, double* /*state*/) const { return false; }

 private:
  IsotropicElasticity elasticity_;
  double density_;
};

/// The largest Young's modulus of `materials` (0 for none): the scale of the penalty
/// terms (ghost faces, rigid-box contact) and of the internal force's round-off.
inline double stiffest_young(const std::vector<std::shared_ptr<const Material>>& materials) {
  double young = 0.0;
  for (const auto& m : materials) young = std::max(young, m->elasticity().young);
  return young;
}

}  // namespace gradmpm
