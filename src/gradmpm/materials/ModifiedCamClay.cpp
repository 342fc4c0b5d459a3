#include "gradmpm/materials/ModifiedCamClay.hpp"

#include <Eigen/LU>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "gradmpm/core/SymmetricTensor.hpp"
#include "gradmpm/io/CaseFile.hpp"
#include "gradmpm/materials/MaterialRegistry.hpp"
#include "gradmpm/materials/Spectral.hpp"

namespace gradmpm {

namespace {
// Response cache: the trial (12), then d_gamma, the returned eps_v^e and eps_v^p, and the
// region (0 elastic, 1 plastic).
constexpr int kGamma = kTrialCacheSize, kVolume = kTrialCacheSize + 1, kPlastic = kTrialCacheSize + 2,
              kRegion = kTrialCacheSize + 3;
static_assert(MaterialResponse::cache_capacity >= kTrialCacheSize + 4);
const Eigen::Vector3d kOnes = Eigen::Vector3d::Ones();
const double kSqrt6 = std::sqrt(6.0), kSqrt23 = std::sqrt(2.0 / 3.0);

/// The elasticity the rest of the program sees (stiffest_young, the gradient step): the
/// law's at the start, K_0 = p_0 / kappa~ and G.
IsotropicElasticity initial_elasticity(const CamClayParameters& p) {
  const double K = p.p0 * (1.0 + p.e0) / p.kappa, G = p.shear_modulus;
  return {9.0 * K * G / (3.0 * K + G), (3.0 * K - 2.0 * G) / (2.0 * (3.0 * K + G))};
}
}  // namespace

ModifiedCamClay::ModifiedCamClay(const CamClayParameters& p, double rho)
    : PlasticLaw(initial_elasticity(p), rho, "plastic volumetric strain eps_v^p (compression positive)"),
      p_(p),
      kt_(p.kappa / (1.0 + p.e0)),
      lt_(p.lambda / (1.0 + p.e0)) {
  if (!(p.kappa > 0.0 && p.lambda > p.kappa && p.M > 0.0 && p.e0 > 0.0 && p.p0 > 0.0 && p.pc0 >= p.p0 &&
        p.shear_modulus > 0.0))
    throw std::invalid_argument(
        "ModifiedCamClay: needs 0 < kappa < lambda, M > 0, e0 > 0, p0 > 0, pc0 >= p0 and G > 0");
}

double ModifiedCamClay::shear_modulus_of(double poisson, double p0, double kappa, double e0) {
  const double K = p0 * (1.0 + e0) / kappa;
  return 3.0 * K * (1.0 - 2.0 * poisson) / (2.0 * (1.0 + poisson));
}

double ModifiedCamClay::pressure(double eps_v_elastic) const { return p_.p0 * std::exp(eps_v_elastic / kt_); }
double ModifiedCamClay::preconsolidation(double eps_v_plastic) const {
  return p_.pc0 * std::exp(eps_v_plastic / (lt_ - kt_));
}

void ModifiedCamClay::update(const Mat3& dF, const double* state_n, double* state, MaterialResponse& out) const {
  const ElasticTrial trial = elastic_trial(dF, unpack_symmetric(state_n));
  const double G = p_.shear_modulus, M2 = p_.M * p_.M, c = 6.0 * G / M2, h = lt_ - kt_;
  const Eigen::Vector3d eps_tr = trial.log_strain();
  const double ev_tr = -eps_tr.sum();
  const Eigen::Vector3d e_tr = eps_tr - eps_tr.mean() * kOnes;
  const double q_tr = kSqrt6 * G * e_tr.norm();
  const double evp_n = state_n[kKappa];
  double ev = ev_tr, dg = 0.0, region = 0.0;
  const double P_tr = pressure(ev_tr), Pc_n = preconsolidation(evp_n);
  if (yields(q_tr * q_tr / M2 + P_tr * (P_tr - Pc_n), P_tr * std::max(P_tr, Pc_n))) {
    // Newton on (eps_v^e, d_gamma): r1 = eps_v^e - eps_v,tr + d_gamma df/dP,
    // r2 = f(P, q) with q = q_tr / (1 + c d_gamma), P_c at eps_v^p,n + eps_v,tr - eps_v^e.
    region = 1.0;
    bool converged = false;
    for (int it = 0; it < 60 && !converged; ++it) {
      const double P = pressure(ev), Pc = preconsolidation(evp_n + ev_tr - ev), q = q_tr / (1.0 + c * dg);
      const double r1 = ev - ev_tr + dg * (2.0 * P - Pc), r2 = q * q / M2 + P * (P - Pc);
      const double scale = std::max(P, Pc);
      converged = std::abs(r1) <= 1e-15 * (1.0 + std::abs(ev_tr)) * 10.0 && std::abs(r2) <= 1e-13 * scale * scale;
      if (converged) break;
      const double J11 = 1.0 + dg * (2.0 * P / kt_ + Pc / h), J12 = 2.0 * P - Pc;
      const double J21 = (2.0 * P - Pc) * P / kt_ + P * Pc / h, J22 = -2.0 * q * q / M2 * c / (1.0 + c * dg);
      const double det = J11 * J22 - J12 * J21;
      double d_ev = -(J22 * r1 - J12 * r2) / det, d_dg = -(-J21 * r1 + J11 * r2) / det;
      // (the exponentials: a step of more than kappa~ in eps_v^e is cut back)
      const double limit = std::abs(d_ev) > kt_ ? kt_ / std::abs(d_ev) : 1.0;
      d_ev *= limit;
      d_dg *= limit;
      ev += d_ev;
      dg = std::max(dg + d_dg, 0.5 * dg);  // (d_gamma stays positive)
    }
    if (!converged) {  // a failed update reads as no balance (Newton cuts the step)
      out.stress = Mat3::Constant(std::numeric_limits<double>::quiet_NaN());
      return;
    }
  }
  const double beta = 1.0 / (1.0 + c * dg), P = pressure(ev);
  const Eigen::Vector3d tau = 2.0 * G * beta * e_tr - P * kOnes;
  const Eigen::Vector3d eps_e = beta * e_tr - ev / 3.0 * kOnes;
  const double evp = evp_n + ev_tr - ev;
  finish_update(trial, tau, eps_e, evp, {dg, ev, evp, region}, state_n, state, out);
}

void ModifiedCamClay::tangent(const MaterialResponse& r, int dim, Mat9& A) const {
  const ElasticTrial trial = load_trial(r);
  const double G = p_.shear_modulus, M2 = p_.M * p_.M, c = 6.0 * G / M2, h = lt_ - kt_;
  const double dg = r.cache[kGamma], ev = r.cache[kVolume], evp = r.cache[kPlastic];
  const Eigen::Vector3d eps_tr = trial.log_strain();
  const Eigen::Vector3d e_tr = eps_tr - eps_tr.mean() * kOnes;
  const double norm_e = e_tr.norm(), q_tr = kSqrt6 * G * norm_e;
  const Eigen::Vector3d n = norm_e > 1e-14 ? Eigen::Vector3d(e_tr / norm_e) : Eigen::Vector3d::Zero();
  const Mat3 one = kOnes * kOnes.transpose(), dev = Mat3::Identity() - one / 3.0;
  const double P = pressure(ev), K = P / kt_, beta = 1.0 / (1.0 + c * dg);
  Mat3 D;
  if (r.cache[kRegion] == 0.0) {
    D = K * one + 2.0 * G * dev;
  } else {
    // [d eps_v^e, d d_gamma] = -J^-1 B [d eps_v,tr, d q_tr] (the linearised return), then
    // tau = -P 1 + sqrt(2/3) q n with q = beta q_tr.
    const double Pc = preconsolidation(evp), q = beta * q_tr;
    Eigen::Matrix2d J, B;
    J << 1.0 + dg * (2.0 * P / kt_ + Pc / h), 2.0 * P - Pc, (2.0 * P - Pc) * P / kt_ + P * Pc / h,
        -2.0 * q * q / M2 * c * beta;
    B << -1.0 - dg * Pc / h, 0.0, -P * Pc / h, 2.0 * q / M2 * beta;
    const Eigen::Matrix2d S = -J.inverse() * B;
    const Eigen::RowVector3d d_ev_tr = -kOnes.transpose(), d_q_tr = kSqrt6 * G * n.transpose();
    const Eigen::RowVector3d d_ev = S(0, 0) * d_ev_tr + S(0, 1) * d_q_tr;
    const Eigen::RowVector3d d_dg = S(1, 0) * d_ev_tr + S(1, 1) * d_q_tr;
    const Eigen::RowVector3d d_q = beta * d_q_tr - q * c * beta * d_dg;
    D = -K * kOnes * d_ev + kSqrt23 * n * d_q + 2.0 * G * beta * (dev - n * n.transpose());
  }
  const Eigen::Vector3d tau = principal_values(r.stress, trial);
  spectral_tangent(trial, tau, 0.0, D, spin_coefficients(trial, G * beta), dim, A);
}

double ModifiedCamClay::elastic_energy_density(const double* state) const {
  const Mat3 e = elastic_strain(state);
  const double ev = -e.trace();
  const Mat3 d = e - e.trace() / 3.0 * Mat3::Identity();
  return p_.p0 * kt_ * std::expm1(ev / kt_) + p_.shear_modulus * d.squaredNorm();
}

bool ModifiedCamClay::start_from_stress(const Mat3& sigma, double* state) const {
  initial_state(state);
  const double P = -sigma.trace() / 3.0;
  if (!(P > 0.0)) return true;  // (no pressure: the caller's check refuses the state)
  const Mat3 s = sigma + P * Mat3::Identity();
  const double q2 = 1.5 * s.squaredNorm();
  pack_symmetric(s / (2.0 * p_.shear_modulus) - kt_ * std::log(P / p_.p0) / 3.0 * Mat3::Identity(), state);
  const double Pc = p_.ocr * (P + q2 / (p_.M * p_.M * P));
  state[kKappa] = (lt_ - kt_) * std::log(Pc / p_.pc0);
  return true;
}

MaterialInfo modified_cam_clay_info() {
  // A table of keys (laid out by hand).
  // clang-format off
  std::vector<KeySpec> keys = {
      {.name = "lambda", .type = KeyType::Number, .min = 0.0, .min_open = true, .allowed = "a slope > kappa", .doc = "lambda, the normal compression line's slope in e - ln p'"},
      {.name = "kappa", .type = KeyType::Number, .min = 0.0, .min_open = true, .allowed = "a slope > 0", .doc = "kappa, the swelling lines' slope in e - ln p'"},
      {.name = "M", .type = KeyType::Number, .min = 0.0, .min_open = true, .allowed = "a slope > 0", .doc = "the critical state line's slope q / p'"},
      {.name = "e0", .type = KeyType::Number, .min = 0.0, .min_open = true, .allowed = "a void ratio > 0", .doc = "the void ratio at the start"},
      {.name = "initial_pressure", .type = KeyType::Number, .min = 0.0, .min_open = true, .allowed = "a pressure > 0",
       .doc = "p_0, the isotropic effective stress the points start at (compression positive; the body's boundary must carry it)"},
      {.name = "preconsolidation_pressure", .type = KeyType::Number, .min = 0.0, .min_open = true, .allowed = "a pressure >= initial_pressure",
       .doc = "p_c0 (= initial_pressure: normally consolidated)"},
      {.name = "overconsolidation_ratio", .type = KeyType::Number, .default_value = 1.0, .min = 1.0, .allowed = "a ratio >= 1",
       .doc = "with [initial_stress]: P_c is this times the pressure where the yield surface through the initial stress meets q = 0 (1: normally consolidated); initial_pressure is then only the elasticity's reference"},
      {.name = "poisson", .type = KeyType::Number, .default_text = "none", .min = -1.0, .max = 0.5, .min_open = true, .max_open = true,
       .allowed = "a Poisson's ratio in (-1, 0.5)", .doc = "G from nu at the initial bulk stiffness p_0 (1 + e0) / kappa (give poisson or shear_modulus)"},
      {.name = "shear_modulus", .type = KeyType::Number, .default_text = "none", .min = 0.0, .min_open = true, .allowed = "a shear modulus > 0",
       .doc = "G, constant (give poisson or shear_modulus)"},
      {.name = "density", .type = KeyType::Number, .default_value = 0.0, .min = 0.0, .allowed = "a density >= 0",
       .doc = "reference mass density rho_0 (body force m_p g)"}};
  // clang-format on
  return {"modified-cam-clay",
          "finite-strain Modified Cam-Clay: pressure-dependent hyperelasticity, elliptic yield surface, hardening by the "
          "plastic volume change (starts at initial_pressure)",
          keys,
          [](const CaseFile& cf, const std::string& prefix, const MaterialInfo& self) -> std::shared_ptr<const Material> {
            const LawKeys in{cf, prefix, self};
            CamClayParameters p;
            p.lambda = in.number("lambda");
            p.kappa = in.number("kappa");
            p.M = in.number("M");
            p.e0 = in.number("e0");
            p.p0 = in.number("initial_pressure");
            p.pc0 = in.number("preconsolidation_pressure");
            p.ocr = in.number("overconsolidation_ratio");
            in.require(p.lambda > p.kappa, "lambda", in.spec("lambda").expected());
            in.require(p.pc0 >= p.p0, "preconsolidation_pressure", in.spec("preconsolidation_pressure").expected());
            in.require(in.has("poisson") != in.has("shear_modulus"), "poisson", "either poisson or shear_modulus (one of them)");
            p.shear_modulus = in.has("shear_modulus")
                                  ? in.number("shear_modulus")
                                  : ModifiedCamClay::shear_modulus_of(in.number("poisson"), p.p0, p.kappa, p.e0);
            return std::make_shared<ModifiedCamClay>(p, in.number("density"));
          }};
}

}  // namespace gradmpm
