#pragma once
// What the finite-strain elasto-plastic laws share: their state (the logarithmic elastic
// strain and the equivalent plastic strain kappa, written as elastic_strain and eps_p) and
// a strength that hardens or softens linearly in kappa down to a residual value.
#include <algorithm>
#include <initializer_list>
#include <string>
#include <vector>

#include "gradmpm/core/SymmetricTensor.hpp"
#include "gradmpm/materials/Material.hpp"
#include "gradmpm/materials/Spectral.hpp"

namespace gradmpm {

/// s(kappa) = max(residual, initial + slope kappa) when softening (slope < 0), else
/// initial + slope kappa.
struct LinearStrength {
  double initial = 0.0, slope = 0.0, residual = 0.0;

  double at(double kappa, bool* at_floor = nullptr) const {
    const double s = initial + slope * kappa;
    const bool floor = slope < 0.0 && s <= residual;
    if (at_floor) *at_floor = floor;
    return floor ? residual : s;
  }
  /// Whether softening from kappa_n (not yet at the floor) by d_kappa passes the floor.
  bool passes_floor(double kappa_n, double d_kappa) const {
    return slope < 0.0 && initial + slope * kappa_n > residual && initial + slope * (kappa_n + d_kappa) < residual;
  }
};

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

 protected:
  static constexpr int kKappa = 6;  ///< state: elastic strain (6), then kappa
  double bulk_modulus() const { return elasticity().lambda + 2.0 * elasticity().mu / 3.0; }
  /// Writes the returned principal stress and elastic strain in the trial's frame, kappa,
  /// and into the response cache the trial, then `extra` (what the law's tangent needs).
  void finish_update(const ElasticTrial& trial, const Eigen::Vector3d& tau, const Eigen::Vector3d& eps_e, double kappa,
                     std::initializer_list<double> extra, double* state, MaterialResponse& out) const {
    const Mat3& n = trial.directions;
    out.stress = n * tau.asDiagonal() * n.transpose();
    pack_symmetric(n * eps_e.asDiagonal() * n.transpose(), state);
    state[kKappa] = kappa;
    store_trial(trial, out);
    std::copy(extra.begin(), extra.end(), out.cache.begin() + kTrialCacheSize);
  }

 private:
  std::vector<StateVariable> vars_;
};

}  // namespace gradmpm
