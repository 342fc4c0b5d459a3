#pragma once
// What the finite-strain elasto-plastic laws share: their state (the logarithmic elastic
// strain and the equivalent plastic strain kappa, written as elastic_strain and eps_p) and
// a strength that hardens or softens linearly in kappa down to a residual value; and the
// implicit-gradient regularisation of softening (docs/shear-bands.md): a regularised law
// also holds the nonlocal kappa_bar (eps_p_nonlocal), which the driver's staggered
// iteration (mpm/ImplicitGradient.hpp) writes into the state the step starts from, and
// its strength is s(kappa_hat), kappa_hat = (1 - m) kappa + m kappa_bar (over-nonlocal).
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <memory>
#include <string>
#include <vector>

#include "gradmpm/core/SymmetricTensor.hpp"
#include "gradmpm/materials/Material.hpp"
#include "gradmpm/materials/Spectral.hpp"

namespace gradmpm {

/// s(kappa) = max(residual, initial + slope kappa) when floored (a softening law: slope <
/// 0), else initial + slope kappa.
struct LinearStrength {
  double initial = 0.0, slope = 0.0, residual = 0.0;
  bool floored = false;  ///< the residual floor applies (softening laws)

  LinearStrength() = default;
  LinearStrength(double s0, double h, double floor) : initial(s0), slope(h), residual(floor), floored(h < 0.0) {}

  double at(double kappa, bool* at_floor = nullptr) const {
    const double s = initial + slope * kappa;
    const bool floor = floored && s <= residual;
    if (at_floor) *at_floor = floor;
    return floor ? residual : s;
  }
  /// Whether softening from kappa_n (not yet at the floor) by d_kappa passes the floor.
  bool passes_floor(double kappa_n, double d_kappa) const {
    return floored && slope < 0.0 && initial + slope * kappa_n > residual &&
           initial + slope * (kappa_n + d_kappa) < residual;
  }
  /// Whether a rising strength at the floor at kappa_n leaves it within d_kappa (the
  /// local strength of a regularised law, whose slope (1 - m) H is positive for m > 1).
  bool leaves_floor(double kappa_n, double d_kappa) const {
    return floored && slope > 0.0 && initial + slope * kappa_n <= residual &&
           initial + slope * (kappa_n + d_kappa) > residual;
  }
  /// The strength as a function of the local kappa with kappa_bar frozen:
  /// s((1 - m) kappa + m kappa_bar), still floored at the residual value.
  LinearStrength over_nonlocal(double kappa_bar, double m) const {
    LinearStrength out = *this;
    out.initial += slope * m * kappa_bar;
    out.slope *= 1.0 - m;
    return out;
  }
};

/// Whether a trial state yields: f > tolerance x the size of the yield function's terms (the
/// current strength at the point). A point left on the surface by the last step returns
/// with f = +-1e-15 of its strength; an exact `f > 0` then chose the plastic or the elastic
/// tangent by round-off, and a step's cuts could not change that choice (AMPLE's VMconst.m
/// takes f / sigma_y > 1e-9; the relative 1e-12 keeps the returns 1e-10 on the surface).
constexpr double kYieldTolerance = 1e-12;
inline bool yields(double f, double strength_scale) { return f > kYieldTolerance * strength_scale; }

class PlasticLaw : public Material {
 public:
  /// `kappa_doc`: how the law defines its equivalent plastic strain.
  PlasticLaw(const IsotropicElasticity& e, double rho, const std::string& kappa_doc)
      : Material(e, rho),
        vars_{{"elastic_strain", StateVariable::Kind::SymmetricTensor, 0.0,
               "logarithmic elastic strain eps_e = 1/2 ln b_e"},
              {"eps_p", StateVariable::Kind::Scalar, 0.0, kappa_doc}} {}
  bool finite_strain() const override { return true; }
  const std::vector<StateVariable>& state_variables() const override { return vars_; }
  Mat3 elastic_strain(const double* state) const override { return unpack_symmetric(state); }
  /// The logarithmic elastic strain whose Kirchhoff stress is sigma (no plastic strain).
  bool start_from_stress(const Mat3& sigma, double* state) const override {
    initial_state(state);
    pack_symmetric(elasticity().strain(sigma), state);
    return true;
  }
  bool softens() const override { return law_strength().slope < 0.0; }
  std::shared_ptr<const Material> regularised(double m) const override {
    std::shared_ptr<PlasticLaw> copy = clone();
    copy->nonlocal_weight_ = m;
    copy->vars_.push_back({"eps_p_nonlocal", StateVariable::Kind::Scalar, 0.0,
                           "nonlocal kappa_bar, kappa_bar - l^2 laplacian kappa_bar = kappa ([regularisation])"});
    return copy;
  }
  bool has_strength() const override { return true; }
  /// The law's strength_divided (its parameters' strength over F), regularised as this one is.
  std::shared_ptr<const Material> strength_reduced(double F) const override {
    std::shared_ptr<PlasticLaw> copy = strength_divided(F);
    if (!copy) return nullptr;
    copy->vars_ = vars_;
    copy->nonlocal_weight_ = nonlocal_weight_;
    return copy;
  }
  /// m of kappa_hat = (1 - m) kappa + m kappa_bar; 0 when the law is not regularised.
  double nonlocal_weight() const { return nonlocal_weight_; }

  static constexpr int kKappa = 6;     ///< state: elastic strain (6), then kappa,
  static constexpr int kNonlocal = 7;  ///< then kappa_bar when regularised

 protected:
  /// The law's strength in its own kappa (yield stress or cohesion).
  virtual const LinearStrength& law_strength() const = 0;
  virtual std::shared_ptr<PlasticLaw> clone() const = 0;
  /// A new law of this kind from its parameters with the strength divided by F (see
  /// Material::strength_reduced); null when the law's strength cannot be reduced.
  virtual std::shared_ptr<PlasticLaw> strength_divided(double /*F*/) const { return nullptr; }
  /// The friction (or dilation) angle, degrees, whose tangent is tan(degrees) / F.
  static double reduced_angle(double degrees, double F) {
    constexpr double rad = 3.14159265358979323846 / 180.0;
    return std::atan(std::tan(degrees * rad) / F) / rad;
  }
  /// The strength the return mapping of one point sees: the law's own, or with
  /// regularisation s(kappa_hat) in the local kappa, kappa_bar frozen at state_n's value.
  LinearStrength local_strength(const double* state_n) const {
    return nonlocal_weight_ > 0.0 ? law_strength().over_nonlocal(state_n[kNonlocal], nonlocal_weight_) : law_strength();
  }
  double bulk_modulus() const { return elasticity().lambda + 2.0 * elasticity().mu / 3.0; }
  /// Writes the returned principal stress and elastic strain in the trial's frame, kappa,
  /// and into the response cache the trial, then `extra` (what the law's tangent needs).
  /// A regularised law carries kappa_bar from state_n.
  void finish_update(const ElasticTrial& trial, const Eigen::Vector3d& tau, const Eigen::Vector3d& eps_e, double kappa,
                     std::initializer_list<double> extra, const double* state_n, double* state,
                     MaterialResponse& out) const {
    if (nonlocal_weight_ > 0.0) state[kNonlocal] = state_n[kNonlocal];
    const Mat3& n = trial.directions;
    out.stress = n * tau.asDiagonal() * n.transpose();
    pack_symmetric(n * eps_e.asDiagonal() * n.transpose(), state);
    state[kKappa] = kappa;
    store_trial(trial, out);
    std::copy(extra.begin(), extra.end(), out.cache.begin() + kTrialCacheSize);
  }

 private:
  std::vector<StateVariable> vars_;
  double nonlocal_weight_ = 0.0;
};

}  // namespace gradmpm
