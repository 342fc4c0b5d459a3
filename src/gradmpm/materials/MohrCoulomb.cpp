#include "gradmpm/materials/MohrCoulomb.hpp"

#include <Eigen/Dense>
#include <bit>
#include <cmath>
#include <numbers>
#include <vector>

#include "gradmpm/io/CaseFile.hpp"
#include "gradmpm/materials/MaterialRegistry.hpp"

namespace gradmpm {

namespace {
// Response cache: the trial (12), the active planes, the strength sigma_c the return
// converged at, and d sigma_c / d kappa in force (0 at the floor).
constexpr int kActive = kTrialCacheSize, kStrength = kTrialCacheSize + 1, kSlope = kTrialCacheSize + 2;
static_assert(MaterialResponse::cache_capacity >= kTrialCacheSize + 3);
const Eigen::Vector3d kOnes = Eigen::Vector3d::Ones();

double ratio(double deg) {
  const double s = std::sin(deg * std::numbers::pi / 180.0);
  return (1.0 + s) / (1.0 - s);
}
/// Eigen's eigenvalues ascend; the return works on sigma_1 >= sigma_2 >= sigma_3.
Eigen::Vector3d descending(const Eigen::Vector3d& v) { return {v[2], v[1], v[0]}; }

/// The candidate active sets of the nine planes, by size (1, 2, 3), then by number.
const std::vector<unsigned>& active_sets() {
  static const std::vector<unsigned> sets = [] {
    std::vector<unsigned> v;
    for (int size = 1; size <= 3; ++size)
      for (unsigned m = 1; m < 512; ++m)
        if (std::popcount(m) == size) v.push_back(m);
    return v;
  }();
  return sets;
}
constexpr unsigned kCutoffPlanes = 0b111000000;  // bits 6-8

using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3, 3>;
using SmallVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 3, 1>;
}  // namespace

MohrCoulomb::MohrCoulomb(const IsotropicElasticity& e, double rho, const MohrCoulombParameters& p)
    : PlasticLaw(e, rho, "equivalent plastic strain kappa = int sqrt(2/3) |d eps_p|"),
      params_(p),
      k_(ratio(p.friction_angle)),
      m_(ratio(p.dilation_angle)),  // equal to k_ when psi = phi
      sigma_t_(p.tension_cutoff),
      cohesion_{p.cohesion, p.hardening, p.residual_cohesion} {
  D_ = e.lambda * kOnes * kOnes.transpose() + 2.0 * e.mu * Mat3::Identity();
  D_inv_ = D_.inverse();
  // The planes a_j . sigma = strength_j and their flow directions b_j: Mohr-Coulomb's six,
  // k sigma_i - sigma_j (the main plane first, then the two beyond its edges sigma_2 =
  // sigma_3 and sigma_1 = sigma_2, then the other three, which the apex needs), and the
  // cut-off's three.
  a_ = {
      {{k_, 0, -1}, {k_, -1, 0}, {0, k_, -1}, {-1, k_, 0}, {-1, 0, k_}, {0, -1, k_}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  b_ = {
      {{m_, 0, -1}, {m_, -1, 0}, {0, m_, -1}, {-1, m_, 0}, {-1, 0, m_}, {0, -1, m_}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
}

std::shared_ptr<PlasticLaw> MohrCoulomb::strength_divided(double F) const {
  MohrCoulombParameters p = params_;
  p.cohesion /= F;
  p.hardening /= F;
  p.residual_cohesion /= F;
  p.tension_cutoff /= F;
  p.friction_angle = reduced_angle(p.friction_angle, F);
  p.dilation_angle = reduced_angle(p.dilation_angle, F);
  return std::make_shared<MohrCoulomb>(elasticity(), density(), p);
}

MohrCoulomb::Region MohrCoulomb::region(const MaterialResponse& r) {
  const unsigned a = static_cast<unsigned>(r.cache[kActive]);
  if (a == 0) return Region::Elastic;
  if (a & kCutoffPlanes) return Region::Tension;
  if (std::popcount(a) == 3) return Region::Apex;
  if (a == 0b101) return Region::EdgeCompression;  // sigma_1 = sigma_2
  if (a == 0b011) return Region::EdgeExtension;    // sigma_2 = sigma_3
  return Region::Plane;
}

MohrCoulomb::Return MohrCoulomb::return_map(const Eigen::Vector3d& tr, double s) const {
  const Return elastic{0, tr, Mat3::Identity(), Eigen::Vector3d::Zero()};
  // In sorted space the plane and the first cut-off plane bound the others; each yields
  // by more than round-off of its terms (materials/PlasticLaw.hpp).
  const bool plane = yields(a_[0].dot(tr) - s, k_ * std::abs(tr[0]) + std::abs(tr[2]) + std::abs(s));
  const bool cut = std::isfinite(sigma_t_) && yields(tr[0] - sigma_t_, std::abs(tr[0]) + sigma_t_);
  if (!plane && !cut) return elastic;
  Return out;
  for (unsigned set : active_sets())
    if (return_onto(set, tr, s, out)) return out;
  return beyond_apex(s);
}

MohrCoulomb::Return MohrCoulomb::return_map(const Eigen::Vector3d& tr, double s, unsigned active) const {
  if (active == 0) return {0, tr, Mat3::Identity(), Eigen::Vector3d::Zero()};
  Return out;
  if (return_onto(active, tr, s, out)) return out;
  return beyond_apex(s);  // the set that return_map(tr, s) found no return onto
}

bool MohrCoulomb::return_onto(unsigned set, const Eigen::Vector3d& tr, double s, Return& out) const {
  const bool cutoff = std::isfinite(sigma_t_);
  if (!cutoff && (set & kCutoffPlanes)) return false;
  auto strength = [&](int j) { return j < 6 ? s : sigma_t_; };
  const double scale = tr.cwiseAbs().maxCoeff() + std::abs(s) + (cutoff ? std::abs(sigma_t_) : 0.0);
  int j_of[3], n = 0;
  for (int j = 0; j < 9; ++j)
    if (set & (1u << j)) j_of[n++] = j;
  Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, 3> A(3, n), DB(3, n);
  SmallVector rhs(n), strong(n);
  for (int i = 0; i < n; ++i) {
    A.col(i) = a_[j_of[i]];
    DB.col(i) = D_ * b_[j_of[i]];
    rhs[i] = a_[j_of[i]].dot(tr) - strength(j_of[i]);
    strong[i] = j_of[i] < 6 ? 1.0 : 0.0;
  }
  const Small M = A.transpose() * DB;
  Eigen::FullPivLU<Small> lu(M);
  lu.setThreshold(1e-12);
  if (lu.rank() < n) return false;
  const SmallVector d_lambda = lu.solve(rhs);
  if (d_lambda.minCoeff() < -1e-12 * scale / D_(0, 0)) return false;
  const Eigen::Vector3d sigma = tr - DB * d_lambda;
  bool admissible = true;
  for (int j = 0; j < (cutoff ? 9 : 6); ++j) admissible = admissible && a_[j].dot(sigma) - strength(j) <= 1e-10 * scale;
  if (!admissible) return false;
  const Small Minv = lu.inverse();
  out.active = set;
  out.sigma = sigma;
  // Three independent planes fix the stress: P vanishes (exactly, not to round-off).
  out.P = n == 3 ? Mat3::Zero() : Mat3(Mat3::Identity() - DB * Minv * A.transpose());
  out.g = DB * (Minv * strong);
  return true;
}

MohrCoulomb::Return MohrCoulomb::beyond_apex(double s) const {
  // No flow directions reach the stress: beyond the apex with too little dilation (psi = 0:
  // deviatoric flow never changes the mean stress). The apex then acts as a cut-off of the
  // mean stress (as Clausen et al. do), or the cut-off's apex when that is lower. Tresca
  // (phi = 0) has no apex: its prism returns every trial to a plane or an edge, so this is
  // reached only by round-off, and the NaN cuts the step.
  const double apex = k_ > 1.0 ? s / (k_ - 1.0) : std::numeric_limits<double>::quiet_NaN();
  const bool cut = std::isfinite(sigma_t_) && !(sigma_t_ >= apex);
  Return out;
  out.active = cut ? kCutoffPlanes : 0b111;
  out.sigma = (cut ? sigma_t_ : apex) * kOnes;
  out.P.setZero();
  out.g = cut || !(k_ > 1.0) ? Eigen::Vector3d::Zero() : Eigen::Vector3d(kOnes / (k_ - 1.0));
  return out;
}

void MohrCoulomb::update(const Mat3& dF, const double* state_n, double* state, MaterialResponse& out) const {
  const ElasticTrial trial = elastic_trial(dF, unpack_symmetric(state_n));
  const Eigen::Vector3d eps_tr = trial.log_strain();
  const Eigen::Vector3d tr = descending(D_ * eps_tr);  // sorted principal trial Kirchhoff stresses
  const double kappa_n = state_n[kKappa], root_k = 2.0 * std::sqrt(k_);
  // sigma_c = 2 sqrt(k) c(kappa(sigma_c)): Newton on the strength (one pass without softening).
  const LinearStrength cohesion = local_strength(state_n);
  double s = root_k * cohesion.at(kappa_n), slope = 0.0, kappa = kappa_n;
  Return ret;
  for (int it = 0;; ++it) {
    ret = return_map(tr, s);
    const Eigen::Vector3d eps_p = D_inv_ * (tr - ret.sigma);
    const double norm = eps_p.norm();
    kappa = kappa_n + std::sqrt(2.0 / 3.0) * norm;
    bool floor = false;
    const double target = root_k * cohesion.at(kappa, &floor);
    slope = ret.active == 0 || floor ? 0.0 : root_k * cohesion.slope;
    const double residual = s - target;
    if (std::abs(residual) <= 1e-13 * std::max(std::abs(s), root_k * cohesion_.initial)) break;
    if (it == 50) {
      ret.sigma.setConstant(std::numeric_limits<double>::quiet_NaN());  // the step is cut
      break;
    }
    const double dkappa_ds = norm > 0.0 ? -std::sqrt(2.0 / 3.0) * eps_p.dot(D_inv_ * ret.g) / norm : 0.0;
    s -= residual / (1.0 - slope * dkappa_ds);
  }
  const Eigen::Vector3d tau = descending(ret.sigma);
  const Eigen::Vector3d eps_e = D_inv_ * tau;
  finish_update(trial, tau, eps_e, kappa, {static_cast<double>(ret.active), s, slope}, state_n, state, out);
}

void MohrCoulomb::tangent(const MaterialResponse& r, int dim, Mat9& A) const {
  const ElasticTrial trial = load_trial(r);
  const Eigen::Vector3d eps = trial.log_strain();
  const Eigen::Vector3d tr = descending(D_ * eps);
  // The active set update() found: the same return, without the search.
  const Return ret = return_map(tr, r.cache[kStrength], static_cast<unsigned>(r.cache[kActive]));
  // d sigma / d trial = P + g w^T, w from the strength equation: d s = slope d kappa,
  // d kappa = sqrt(2/3) nu . D^-1 ((I - P) d tr - g d s), nu = eps_p / |eps_p|.
  Mat3 ds = ret.P;
  const double slope = r.cache[kSlope];
  const Eigen::Vector3d eps_p = D_inv_ * (tr - ret.sigma);
  if (slope != 0.0 && eps_p.norm() > 0.0) {
    const Eigen::Vector3d nu = eps_p / eps_p.norm();
    const double beta = slope * std::sqrt(2.0 / 3.0);
    const Eigen::Vector3d w =
        beta / (1.0 + beta * nu.dot(D_inv_ * ret.g)) * (D_inv_ * (Mat3::Identity() - ret.P)).transpose() * nu;
    ds += ret.g * w.transpose();
  }
  // D_ab = d tau_a / d eps_b in Eigen's (ascending) order: reverse both indices.
  Mat3 D;
  const Mat3 Ds = ds * D_;  // sorted order
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) D(a, b) = Ds(2 - a, 2 - b);
  const Eigen::Vector3d tau = descending(ret.sigma);
  // c_ab = (tau_a - tau_b) / (l_a - l_b) = [(tau_a - tau_b) / (eps_a - eps_b)] theta_ab / 2,
  // the bracket tending to D_aa - D_ab when eps_a = eps_b.
  const Eigen::Vector3d& l = trial.stretch2;
  Eigen::Vector3d spin;
  const int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (int k = 0; k < 3; ++k) {
    const int a = pairs[k][0], b = pairs[k][1];
    const double de = eps[a] - eps[b];
    const double slope_ab = std::abs(de) > 1e-10 ? (tau[a] - tau[b]) / de : D(a, a) - D(a, b);
    spin[k] = 0.5 * slope_ab * log_divided_difference(l[a], l[b]);
  }
  spectral_tangent(trial, tau, 0.0, D, spin, dim, A);
}

MaterialInfo mohr_coulomb_info() {
  std::vector<KeySpec> keys = isotropic_elasticity_keys();
  // A table of keys (laid out by hand).
  // clang-format off
  keys.push_back({.name = "cohesion", .type = KeyType::Number, .min = 0.0, .min_open = true, .allowed = "a cohesion > 0", .doc = "c"});
  keys.push_back({.name = "friction_angle", .type = KeyType::Number, .min = 0.0, .max = 90.0, .max_open = true,
                  .allowed = "an angle in degrees in [0, 90)", .doc = "phi, degrees; 0: Tresca (strength c in shear)"});
  keys.push_back({.name = "dilation_angle", .type = KeyType::Number, .min = 0.0, .max = 90.0, .max_open = true,
                  .allowed = "an angle in degrees in [0, friction_angle]", .doc = "psi, degrees; psi < phi: non-associated flow, non-symmetric tangent"});
  keys.push_back({.name = "hardening", .type = KeyType::Number, .default_value = 0.0, .doc = "H = dc / d eps_p; negative: softening"});
  keys.push_back({.name = "residual_cohesion", .type = KeyType::Number, .default_value = 0.0, .min = 0.0,
                  .allowed = "a residual cohesion >= 0", .doc = "the cohesion softening stops at (H < 0); at most cohesion"});
  keys.push_back({.name = "tension_cutoff", .type = KeyType::Number, .default_text = "none", .min = 0.0,
                  .allowed = "a tensile strength >= 0", .doc = "sigma_t: the largest principal stress (Rankine cut-off, associated); none: only Mohr-Coulomb's apex"});
  // clang-format on
  return {
      "mohr-coulomb",
      "finite-strain Mohr-Coulomb elasto-plasticity, non-associated, cohesion hardening or softening, optional tension "
      "cut-off",
      keys,
      [](const CaseFile& cf, const std::string& prefix, const MaterialInfo& self) -> std::shared_ptr<const Material> {
        const LawKeys in{cf, prefix, self};
        MohrCoulombParameters p{in.number("cohesion"), in.number("friction_angle"), in.number("dilation_angle"),
                                in.number("hardening"), in.number("residual_cohesion")};
        if (in.has("tension_cutoff")) p.tension_cutoff = in.number("tension_cutoff");
        in.require(p.dilation_angle <= p.friction_angle, "dilation_angle", in.spec("dilation_angle").expected());
        in.require(p.residual_cohesion <= p.cohesion, "residual_cohesion", "a residual cohesion <= cohesion");
        const ElasticSolid s = read_elastic_solid(cf, prefix, self);
        return std::make_shared<MohrCoulomb>(s.elasticity, s.density, p);
      }};
}

}  // namespace gradmpm
