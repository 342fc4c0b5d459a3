#include "gradmpm/materials/VonMises.hpp"

#include <cmath>

#include "gradmpm/core/SymmetricTensor.hpp"
#include "gradmpm/io/CaseFile.hpp"
#include "gradmpm/materials/MaterialRegistry.hpp"
#include "gradmpm/materials/Spectral.hpp"

namespace gradmpm {

namespace {
// Response cache: the trial (12, materials/Spectral.hpp), then beta and the N(x)N
// coefficient of the algorithmic tangent (both 1 and 0 in an elastic step).
constexpr int kBeta = kTrialCacheSize, kFlow = kTrialCacheSize + 1;
static_assert(MaterialResponse::cache_capacity >= 14);
const Eigen::Vector3d kOnes = Eigen::Vector3d::Ones();
}  // namespace

VonMises::VonMises(const IsotropicElasticity& e, double rho, const VonMisesParameters& p)
    : PlasticLaw(e, rho, "equivalent plastic strain kappa = int sqrt(2/3) |d eps_p|"),
      params_(p),
      yield_{p.yield_stress, p.hardening, p.residual_yield_stress} {}

void VonMises::update(const Mat3& dF, const double* state_n, double* state, MaterialResponse& out) const {
  const ElasticTrial trial = elastic_trial(dF, unpack_symmetric(state_n));
  const double K = bulk_modulus(), mu = elasticity().mu;
  const Eigen::Vector3d eps_tr = trial.log_strain();
  const double volumetric = eps_tr.sum();
  const Eigen::Vector3d s_tr = 2.0 * mu * (eps_tr - volumetric / 3.0 * kOnes);
  const double q_tr = std::sqrt(1.5) * s_tr.norm();
  const double kappa_n = state_n[kKappa];
  const LinearStrength yield = local_strength(state_n);
  bool at_floor = false;
  const double strength = yield.at(kappa_n, &at_floor), f = q_tr - strength;

  Eigen::Vector3d eps_e = eps_tr, tau = K * volumetric * kOnes + s_tr;
  double kappa = kappa_n, beta = 1.0, flow = 0.0;
  if (yields(f, strength)) {  // plastic: return to the yield surface
    double H = at_floor ? 0.0 : yield.slope;
    double d_gamma = f / (3.0 * mu + H);
    // Softening steeper than -3 mu: q_tr - 3 mu d_gamma - sigma_y(kappa_n + d_gamma) grows
    // with d_gamma down to the floor, so its one root lies on the floor.
    if (3.0 * mu + H <= 0.0 || yield.passes_floor(kappa_n, d_gamma)) {
      H = 0.0;  // the floor is reached within the step
      d_gamma = (q_tr - yield.residual) / (3.0 * mu);
    } else if (yield.leaves_floor(kappa_n, d_gamma)) {  // regularised: a rising strength
      H = yield.slope;
      d_gamma = (q_tr - (yield.initial + H * kappa_n)) / (3.0 * mu + H);
    }
    beta = 1.0 - 3.0 * mu * d_gamma / q_tr;
    flow = 2.0 * mu * (1.0 - beta - 3.0 * mu / (3.0 * mu + H));
    tau = K * volumetric * kOnes + beta * s_tr;
    eps_e = eps_tr - d_gamma * 1.5 * s_tr / q_tr;
    kappa = kappa_n + d_gamma;
  }
  finish_update(trial, tau, eps_e, kappa, {beta, flow}, state_n, state, out);
}

void VonMises::tangent(const MaterialResponse& r, int dim, Mat9& A) const {
  const ElasticTrial trial = load_trial(r);
  const double mu = elasticity().mu, K = bulk_modulus();
  const double beta = r.cache[kBeta], flow = r.cache[kFlow];
  const Eigen::Vector3d tau = principal_values(r.stress, trial);
  // D = (K - 2 mu beta / 3) 1(x)1 [kept apart] + 2 mu beta I + flow N(x)N
  Mat3 D = 2.0 * mu * beta * Mat3::Identity();
  const Eigen::Vector3d s = tau - tau.mean() * kOnes;
  if (flow != 0.0 && s.norm() > 0.0) {
    const Eigen::Vector3d N = s / s.norm();
    D += flow * N * N.transpose();
  }
  // (tau_a - tau_b) / (l_a - l_b) = mu beta theta_ab
  spectral_tangent(trial, tau, K - 2.0 * mu * beta / 3.0, D, spin_coefficients(trial, mu * beta), dim, A);
}

MaterialInfo von_mises_info() {
  std::vector<KeySpec> keys = isotropic_elasticity_keys();
  // A table of keys (laid out by hand).
  // clang-format off
  keys.push_back({.name = "yield_stress", .type = KeyType::Number, .min = 0.0, .min_open = true,
                  .allowed = "a yield stress > 0", .doc = "sigma_y0, the initial uniaxial yield stress (c = sigma_y0 / sqrt 3)"});
  keys.push_back({.name = "hardening", .type = KeyType::Number, .default_value = 0.0,
                  .doc = "H = d sigma_y / d eps_p, linear isotropic; negative: softening"});
  keys.push_back({.name = "residual_yield_stress", .type = KeyType::Number, .default_value = 0.0, .min = 0.0,
                  .allowed = "a residual yield stress >= 0", .doc = "the yield stress softening stops at (H < 0); at most yield_stress"});
  // clang-format on
  return {
      "von-mises", "finite-strain von Mises elasto-plasticity, linear hardening or softening", keys,
      [](const CaseFile& cf, const std::string& prefix, const MaterialInfo& self) -> std::shared_ptr<const Material> {
        const LawKeys in{cf, prefix, self};
        const VonMisesParameters p{in.number("yield_stress"), in.number("hardening"),
                                   in.number("residual_yield_stress")};
        in.require(p.residual_yield_stress <= p.yield_stress, "residual_yield_stress",
                   "a residual yield stress <= yield_stress");
        const ElasticSolid s = read_elastic_solid(cf, prefix, self);
        return std::make_shared<VonMises>(s.elasticity, s.density, p);
      }};
}

}  // namespace gradmpm
