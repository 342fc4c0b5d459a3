#include "gradmpm/materials/DruckerPrager.hpp"

#include <cmath>
#include <numbers>

#include "gradmpm/core/SymmetricTensor.hpp"
#include "gradmpm/io/CaseFile.hpp"
#include "gradmpm/materials/MaterialRegistry.hpp"
#include "gradmpm/materials/Spectral.hpp"

namespace gradmpm {

namespace {
// Response cache: the trial (12), then beta = 1 - G d_gamma / sqrt(J2_trial), the region
// (0 elastic, 1 cone, 2 apex) and the hardening modulus in force (0 at the floor).
constexpr int kBeta = kTrialCacheSize, kRegion = kTrialCacheSize + 1, kHardening = kTrialCacheSize + 2;
static_assert(MaterialResponse::cache_capacity >= 15);
const Eigen::Vector3d kOnes = Eigen::Vector3d::Ones();

/// (eta, xi) of the cone fitted to angle `deg` (friction or dilation).
std::pair<double, double> cone(double deg, const std::string& fit) {
  const double a = deg * std::numbers::pi / 180.0;
  if (fit == "plane-strain") {
    const double t = std::tan(a), d = std::sqrt(9.0 + 12.0 * t * t);
    return {3.0 * t / d, 3.0 / d};
  }
  const double s = std::sin(a), d = std::sqrt(3.0) * (fit == "outer" ? 3.0 - s : 3.0 + s);
  return {6.0 * s / d, 6.0 * std::cos(a) / d};
}
}  // namespace

DruckerPrager::DruckerPrager(const IsotropicElasticity& e, double rho, const DruckerPragerParameters& p)
    : PlasticLaw(e, rho, "equivalent plastic strain kappa = int xi d_gamma"),
      params_(p),
      cohesion_{p.cohesion, p.hardening, p.residual_cohesion} {
  std::tie(eta_, xi_) = cone(p.friction_angle, p.fit);
  eta_bar_ = cone(p.dilation_angle, p.fit).first;  // equal to eta_ when psi = phi
}

std::shared_ptr<PlasticLaw> DruckerPrager::strength_divided(double F) const {
  DruckerPragerParameters p = params_;
  p.cohesion /= F;
  p.hardening /= F;
  p.residual_cohesion /= F;
  p.friction_angle = reduced_angle(p.friction_angle, F);
  p.dilation_angle = reduced_angle(p.dilation_angle, F);
  return std::make_shared<DruckerPrager>(elasticity(), density(), p);
}

void DruckerPrager::update(const Mat3& dF, const double* state_n, double* state, MaterialResponse& out) const {
  const ElasticTrial trial = elastic_trial(dF, unpack_symmetric(state_n));
  const double G = elasticity().mu, K = bulk_modulus();
  const Eigen::Vector3d eps_tr = trial.log_strain();
  const double p_tr = K * eps_tr.sum();
  const Eigen::Vector3d s_tr = 2.0 * G * (eps_tr - eps_tr.mean() * kOnes);
  const double j2_tr = s_tr.norm() / std::sqrt(2.0);  // sqrt(J2)
  const double kappa_n = state_n[kKappa];
  const LinearStrength cohesion = local_strength(state_n);
  bool at_floor = false;
  const double c_n = cohesion.at(kappa_n, &at_floor);
  double H = at_floor ? 0.0 : cohesion.slope;
  const double phi = j2_tr + eta_ * p_tr - xi_ * c_n;

  Eigen::Vector3d s = s_tr;
  double p = p_tr, kappa = kappa_n, beta = 1.0, region = 0.0;
  if (yields(phi, xi_ * c_n + eta_ * std::abs(p_tr))) {
    // Smooth cone: d_gamma from Phi(d_gamma) = 0 (linear in d_gamma with linear hardening).
    // Softening steeper than the elastic stiffness (a denominator <= 0): Phi grows with
    // d_gamma down to the floor, so its one root lies on the floor.
    const double stiffness = G + K * eta_ * eta_bar_ + xi_ * xi_ * H;
    double d_gamma = phi / stiffness;
    if (stiffness <= 0.0 || cohesion.passes_floor(kappa_n, xi_ * d_gamma)) {
      H = 0.0;
      d_gamma = (j2_tr + eta_ * p_tr - xi_ * cohesion.residual) / (G + K * eta_ * eta_bar_);
    } else if (cohesion.leaves_floor(kappa_n, xi_ * d_gamma)) {  // regularised: a rising strength
      H = cohesion.slope;
      d_gamma =
          (j2_tr + eta_ * p_tr - xi_ * (cohesion.initial + H * kappa_n)) / (G + K * eta_ * eta_bar_ + xi_ * xi_ * H);
    }
    if (j2_tr - G * d_gamma >= 0.0 || eta_ == 0.0) {  // (phi = 0: a von Mises cylinder, no apex)
      d_gamma = std::min(d_gamma, j2_tr / G);
      region = 1.0;
      beta = 1.0 - G * d_gamma / j2_tr;
      s = beta * s_tr;
      p = p_tr - K * eta_bar_ * d_gamma;
      kappa = kappa_n + xi_ * d_gamma;
    } else {  // apex: s = 0, p on the apex of the current cone
      region = 2.0;
      H = at_floor ? 0.0 : cohesion.slope;
      // alpha = xi / eta_bar relates kappa to the plastic volume change; with psi = 0 there
      // is none and the apex acts as a tension cut-off (kappa unchanged, no stiffness).
      const double alpha = eta_bar_ > 0.0 ? xi_ / eta_bar_ : 0.0, b = xi_ / eta_;
      double dv = (p_tr - b * c_n) / (K + alpha * b * H);
      if (K + alpha * b * H <= 0.0 || cohesion.passes_floor(kappa_n, alpha * dv)) {
        H = 0.0;
        dv = (p_tr - b * cohesion.residual) / K;
      } else if (cohesion.leaves_floor(kappa_n, alpha * dv)) {
        H = cohesion.slope;
        dv = (p_tr - b * (cohesion.initial + H * kappa_n)) / (K + alpha * b * H);
      }
      beta = 0.0;
      s.setZero();
      p = p_tr - K * dv;
      kappa = kappa_n + alpha * dv;
    }
  }
  const Eigen::Vector3d tau = s + p * kOnes, eps_e = s / (2.0 * G) + p / (3.0 * K) * kOnes;
  finish_update(trial, tau, eps_e, kappa, {beta, region, H}, state_n, state, out);
}

void DruckerPrager::tangent(const MaterialResponse& r, int dim, Mat9& A) const {
  const ElasticTrial trial = load_trial(r);
  const double G = elasticity().mu, K = bulk_modulus();
  const double beta = r.cache[kBeta], H = r.cache[kHardening];
  const int region = static_cast<int>(r.cache[kRegion]);
  const Eigen::Vector3d tau = principal_values(r.stress, trial);
  const Mat3 I = Mat3::Identity(), one = kOnes * kOnes.transpose();
  Mat3 D = K * one + 2.0 * G * beta * (I - one / 3.0);  // elastic when beta = 1
  if (region == 1) {
    // de Souza Neto et al., eq. (8.100) in principal space; N = s / |s| (s is parallel
    // to the trial deviator), G d_gamma / sqrt(J2_trial) = 1 - beta.
    const double Ainv = 1.0 / (G + K * eta_ * eta_bar_ + xi_ * xi_ * H);
    const Eigen::Vector3d s = tau - tau.mean() * kOnes, N = s / s.norm();
    D += 2.0 * G * ((1.0 - beta) - G * Ainv) * N * N.transpose() -
         std::sqrt(2.0) * G * Ainv * K * (eta_ * N * kOnes.transpose() + eta_bar_ * kOnes * N.transpose()) -
         K * K * eta_ * eta_bar_ * Ainv * one;
  } else if (region == 2) {
    const double alpha = eta_bar_ > 0.0 ? xi_ / eta_bar_ : 0.0, b = xi_ / eta_;
    D = K * (1.0 - K / (K + alpha * b * H)) * one;
  }
  spectral_tangent(trial, tau, 0.0, D, spin_coefficients(trial, G * beta), dim,
                   A);  // tau_a - tau_b = G beta (ln l_a - ln l_b)
}

MaterialInfo drucker_prager_info() {
  std::vector<KeySpec> keys = isotropic_elasticity_keys();
  // A table of keys (laid out by hand).
  // clang-format off
  keys.push_back({.name = "cohesion", .type = KeyType::Number, .min = 0.0, .min_open = true, .allowed = "a cohesion > 0", .doc = "c0"});
  keys.push_back({.name = "friction_angle", .type = KeyType::Number, .min = 0.0, .max = 90.0, .max_open = true,
                  .allowed = "an angle in degrees in [0, 90)", .doc = "phi, degrees"});
  keys.push_back({.name = "dilation_angle", .type = KeyType::Number, .min = 0.0, .max = 90.0, .max_open = true,
                  .allowed = "an angle in degrees in [0, friction_angle]", .doc = "psi, degrees; psi < phi: non-associated flow, non-symmetric tangent"});
  keys.push_back({.name = "fit", .type = KeyType::String, .default_value = std::string("plane-strain"), .choices = {"plane-strain", "outer", "inner"},
                  .doc = "the cone fitted to Mohr-Coulomb: plane-strain collapse loads, or the compressive (outer) or tensile (inner) meridian"});
  keys.push_back({.name = "hardening", .type = KeyType::Number, .default_value = 0.0, .doc = "H = dc / d eps_p; negative: softening"});
  keys.push_back({.name = "residual_cohesion", .type = KeyType::Number, .default_value = 0.0, .min = 0.0,
                  .allowed = "a residual cohesion >= 0", .doc = "the cohesion softening stops at (H < 0); at most cohesion"});
  // clang-format on
  return {
      "drucker-prager",
      "finite-strain Drucker-Prager elasto-plasticity, non-associated, cohesion hardening or softening", keys,
      [](const CaseFile& cf, const std::string& prefix, const MaterialInfo& self) -> std::shared_ptr<const Material> {
        const LawKeys in{cf, prefix, self};
        const DruckerPragerParameters p{in.number("cohesion"),       in.number("friction_angle"),
                                        in.number("dilation_angle"), in.string("fit"),
                                        in.number("hardening"),      in.number("residual_cohesion")};
        in.require(p.dilation_angle <= p.friction_angle, "dilation_angle", in.spec("dilation_angle").expected());
        in.require(p.residual_cohesion <= p.cohesion, "residual_cohesion", "a residual cohesion <= cohesion");
        const ElasticSolid s = read_elastic_solid(cf, prefix, self);
        return std::make_shared<DruckerPrager>(s.elasticity, s.density, p);
      }};
}

}  // namespace gradmpm
