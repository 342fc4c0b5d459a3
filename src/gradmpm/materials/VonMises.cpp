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
constexpr int kBeta = 12, kFlow = 13;
static_assert(MaterialResponse::cache_capacity >= 14);
constexpr int kKappa = 6;  // state: elastic strain (6), then kappa
const Eigen::Vector3d kOnes = Eigen::Vector3d::Ones();
}  // namespace

VonMises::VonMises(const IsotropicElasticity& e, double rho, const VonMisesParameters& p) : Material(e, rho), p_(p) {}

const std::vector<StateVariable>& VonMises::state_variables() const {
  static const std::vector<StateVariable> vars = {
      {"elastic_strain", StateVariable::Kind::SymmetricTensor, 0.0, "logarithmic elastic strain eps_e = 1/2 ln b_e"},
      {"eps_p", StateVariable::Kind::Scalar, 0.0, "equivalent plastic strain kappa = int sqrt(2/3) |d eps_p|"}};
  return vars;
}

Mat3 VonMises::elastic_strain(const double* state) const { return unpack_symmetric(state); }

double VonMises::yield_stress(double kappa, bool* at_floor) const {
  const double s = p_.yield_stress + p_.hardening * kappa;
  const bool floor = p_.hardening < 0.0 && s <= p_.residual_yield_stress;
  if (at_floor) *at_floor = floor;
  return floor ? p_.residual_yield_stress : s;
}

void VonMises::update(const Mat3& dF, const double* state_n, double* state, MaterialResponse& out) const {
  const ElasticTrial trial = elastic_trial(dF, unpack_symmetric(state_n));
  const IsotropicElasticity& e = elasticity();
  const double K = e.lambda + 2.0 * e.mu / 3.0, mu = e.mu;
  const Eigen::Vector3d eps_tr = trial.log_strain();
  const double volumetric = eps_tr.sum();
  const Eigen::Vector3d s_tr = 2.0 * mu * (eps_tr - volumetric / 3.0 * kOnes);
  const double q_tr = std::sqrt(1.5) * s_tr.norm();
  const double kappa_n = state_n[kKappa];
  bool at_floor = false;
  const double f = q_tr - yield_stress(kappa_n, &at_floor);

  Eigen::Vector3d eps_e = eps_tr, tau = K * volumetric * kOnes + s_tr;
  double kappa = kappa_n, beta = 1.0, flow = 0.0;
  if (f > 0.0) {  // plastic: return to the yield surface
    double H = at_floor ? 0.0 : p_.hardening;
    double d_gamma = f / (3.0 * mu + H);
    if (!at_floor && p_.hardening < 0.0 &&
        p_.yield_stress + p_.hardening * (kappa_n + d_gamma) < p_.residual_yield_stress) {
      H = 0.0;  // the floor is reached within the step
      d_gamma = (q_tr - p_.residual_yield_stress) / (3.0 * mu);
    }
    beta = 1.0 - 3.0 * mu * d_gamma / q_tr;
    flow = 2.0 * mu * (1.0 - beta - 3.0 * mu / (3.0 * mu + H));
    tau = K * volumetric * kOnes + beta * s_tr;
    eps_e = eps_tr - d_gamma * 1.5 * s_tr / q_tr;
    kappa = kappa_n + d_gamma;
  }
  const Mat3& n = trial.directions;
  out.stress = n * tau.asDiagonal() * n.transpose();
  pack_symmetric(n * eps_e.asDiagonal() * n.transpose(), state);
  state[kKappa] = kappa;
  store_trial(trial, out);
  out.cache[kBeta] = beta;
  out.cache[kFlow] = flow;
}

void VonMises::tangent(const MaterialResponse& r, int dim, Mat9& A) const {
  const ElasticTrial trial = load_trial(r);
  const Mat3& n = trial.directions;
  const double mu = elasticity().mu, K = elasticity().lambda + 2.0 * mu / 3.0;
  const double beta = r.cache[kBeta], flow = r.cache[kFlow];
  Eigen::Vector3d tau;  // principal Kirchhoff stresses
  for (int a = 0; a < 3; ++a) tau[a] = n.col(a).dot(r.stress * n.col(a));
  // D = (K - 2 mu beta / 3) 1(x)1 [kept apart] + 2 mu beta I + flow N(x)N
  Mat3 D = 2.0 * mu * beta * Mat3::Identity();
  const Eigen::Vector3d s = tau - tau.mean() * kOnes;
  if (flow != 0.0 && s.norm() > 0.0) {
    const Eigen::Vector3d N = s / s.norm();
    D += flow * N * N.transpose();
  }
  const Eigen::Vector3d& l = trial.stretch2;
  const double c = mu * beta;  // (tau_a - tau_b) / (l_a - l_b) = mu beta theta_ab
  const Eigen::Vector3d spin(c * log_divided_difference(l[0], l[1]), c * log_divided_difference(l[0], l[2]),
                             c * log_divided_difference(l[1], l[2]));
  spectral_tangent(trial, tau, K - 2.0 * mu * beta / 3.0, D, spin, dim, A);
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
        const ElasticSolid s = read_elastic_solid(cf, prefix, self);
        VonMisesParameters p;
        p.yield_stress = read_number(cf, prefix, self.keys[3]);
        p.hardening = read_number(cf, prefix, self.keys[4]);
        p.residual_yield_stress = read_number(cf, prefix, self.keys[5]);
        cf.require(p.residual_yield_stress <= p.yield_stress, prefix + ".residual_yield_stress",
                   "a residual yield stress <= yield_stress");
        return std::make_shared<VonMises>(s.elasticity, s.density, p);
      }};
}

}  // namespace gradmpm
