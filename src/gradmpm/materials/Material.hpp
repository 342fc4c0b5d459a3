#pragma once
// The constitutive interface of the implicit MPM. A material answers, for one point and
// one Newton iterate, "given the deformation-gradient increment dF of this load step and
// the history at the start of the step, what are the stress and the new history?"
// (update), and "what is the consistent tangent at that state?" (tangent). The two are
// separate because Newton needs the tangent only when the residual has not converged,
// and the global assembly forms it point by point without storing it. Tensors are 3x3 in every dimension (plane strain and 1D uniaxial
// strain embed their dim x dim blocks); fourth-order tensors are 9x9 with row i*3+j and
// column k*3+l.
#include <Eigen/Core>
#include <memory>
#include <string>

namespace gradmpm {

using Mat3 = Eigen::Matrix3d;
using Mat9 = Eigen::Matrix<double, 9, 9>;

/// What update() leaves for the caller and for tangent().
struct MaterialResponse {
  Mat3 stress;                ///< Kirchhoff tau (finite strain) or Cauchy sigma (small strain)
  Mat3 strain;                ///< new elastic (logarithmic or small) strain: the history to keep
  Eigen::Vector3d principal;  ///< finite strain: principal values of the trial b_e
  Mat3 directions;            ///< finite strain: their directions (columns)
};

class Material {
 public:
  virtual ~Material() = default;
  /// true: updated-Lagrangian finite strain (stress is Kirchhoff, gradients are taken in
  /// the current configuration); false: incremental small strain on the configuration at
  /// the start of the load step.
  virtual bool finite_strain() const = 0;
  /// `dF`: deformation gradient of the step's displacement increment, I + d(du)/dx_n.
  /// `strain_n`: the history (elastic strain) at the start of the step.
  virtual void update(const Mat3& dF, const Mat3& strain_n, MaterialResponse& out) const = 0;
  /// The consistent tangent at the state `r` that update() returned:
  /// A_ijkl with d(stress_ij grad_j eta_i) = grad_j eta_i A_ijkl grad_l du_k.
  /// Entries with every index below `dim` are computed (plane strain and 1D need no
  /// more); a material may leave the others zero. dim = 3 gives the whole tensor.
  virtual void tangent(const MaterialResponse& r, int dim, Mat9& A) const = 0;
  virtual std::string name() const = 0;

  /// Isotropic elasticity D : eps (lambda tr eps I + 2 mu eps) and its inverse. The
  /// gradient step uses them to pair smoothed strains with stresses (gradient
  /// elasticity is a linear theory; with Hencky, eps is the logarithmic strain and the
  /// stress the Kirchhoff stress).
  Mat3 elastic_stress(const Mat3& eps) const;
  Mat3 elastic_strain(const Mat3& stress) const;

  double density = 0.0;  ///< reference mass density rho_0
  double young = 0.0;
  double poisson = 0.0;
};

/// Isotropic elasticity tensor D_ijkl = lambda d_ij d_kl + mu (d_ik d_jl + d_il d_jk).
Mat9 isotropic_elasticity(double young, double poisson);

/// sigma = D : eps with eps accumulated from sym(dF - I): small-strain linear elasticity.
class LinearElastic final : public Material {
 public:
  LinearElastic(double young, double poisson, double rho);
  bool finite_strain() const override { return false; }
  void update(const Mat3& dF, const Mat3& strain_n, MaterialResponse& out) const override;
  void tangent(const MaterialResponse&, int, Mat9& A) const override { A = D_; }
  std::string name() const override { return "linear-elastic"; }

 private:
  Mat9 D_;
};

/// Hencky (logarithmic-strain) hyperelasticity: tau = D : eps_e, eps_e = 1/2 ln b_e,
/// b_e = dF exp(2 eps_e,n) dF^T, sigma = tau / det F. The consistent tangent is
/// A = 1/2 D : L : B - tau_il d_jk with L = d ln(b)/d b and B_pqkl = d_pk b_lq + d_qk b_pl.
class Hencky final : public Material {
 public:
  Hencky(double young, double poisson, double rho);
  bool finite_strain() const override { return true; }
  void update(const Mat3& dF, const Mat3& strain_n, MaterialResponse& out) const override;
  void tangent(const MaterialResponse& r, int dim, Mat9& A) const override;
  std::string name() const override { return "hencky"; }

 private:
  Mat9 D_;
  double lambda_, mu_;
};

}  // namespace gradmpm
