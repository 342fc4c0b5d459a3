#include "gradmpm/materials/MohrCoulomb.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <numbers>

#include "gradmpm/io/CaseFile.hpp"
#include "gradmpm/materials/MaterialRegistry.hpp"

namespace gradmpm {

namespace {
// Response cache: the trial (12), the region, then d sigma / d sigma_trial in sorted
// (descending) principal order can be recomputed from the trial, so only the region.
constexpr int kRegion = kTrialCacheSize;
static_assert(MaterialResponse::cache_capacity >= kTrialCacheSize + 1);
const Eigen::Vector3d kOnes = Eigen::Vector3d::Ones();

double ratio(double deg) {
  const double s = std::sin(deg * std::numbers::pi / 180.0);
  return (1.0 + s) / (1.0 - s);
}
/// Eigen's eigenvalues ascend; the return works on sigma_1 >= sigma_2 >= sigma_3.
Eigen::Vector3d descending(const Eigen::Vector3d& v) { return {v[2], v[1], v[0]}; }
}  // namespace

MohrCoulomb::MohrCoulomb(const IsotropicElasticity& e, double rho, const MohrCoulombParameters& p)
    : PlasticLaw(e, rho, "equivalent plastic strain kappa = int sqrt(2/3) |dev d eps_p|"),
      k_(ratio(p.friction_angle)),
      m_(ratio(p.dilation_angle)),  // equal to k_ when psi = phi
      sigma_c_(2.0 * p.cohesion * std::sqrt(ratio(p.friction_angle))) {
  D_ = e.lambda * kOnes * kOnes.transpose() + 2.0 * e.mu * Mat3::Identity();
}

MohrCoulomb::Region MohrCoulomb::region(const MaterialResponse& r) {
  return static_cast<Region>(static_cast<int>(r.cache[kRegion]));
}

MohrCoulomb::Region MohrCoulomb::return_map(const Eigen::Vector3d& tr, Eigen::Vector3d& sigma, Mat3& ds) const {
  ds = Mat3::Identity();
  sigma = tr;
  if (yield(tr) <= 0.0) return Region::Elastic;
  const Eigen::Vector3d a(k_, 0.0, -1.0), b(m_, 0.0, -1.0), Db = D_ * b;
  // The plane: sigma = tr - d_lambda D b.
  const double d_lambda = yield(tr) / a.dot(Db);
  const Eigen::Vector3d plane = tr - d_lambda * Db;
  if (plane[0] >= plane[1] && plane[1] >= plane[2]) {
    sigma = plane;
    ds = Mat3::Identity() - Db * a.transpose() / a.dot(Db);
    return Region::Plane;
  }
  // An edge: sigma = apex + t r, the return direction in the span of the two active flow
  // directions, so t = n.(tr - apex) / n.r with n normal to that span.
  const Eigen::Vector3d apex = sigma_c_ / (k_ - 1.0) * kOnes;
  const Eigen::Vector3d r1(1.0, 1.0, k_), r2(1.0, k_, k_);                   // sigma_1 = sigma_2, sigma_2 = sigma_3
  const Eigen::Vector3d n1 = Db.cross(D_ * Eigen::Vector3d(0.0, m_, -1.0));  // with the surface of sigma_1 <-> sigma_2
  const Eigen::Vector3d n2 = Db.cross(D_ * Eigen::Vector3d(m_, -1.0, 0.0));  // with the surface of sigma_2 <-> sigma_3
  const double t1 = n1.dot(tr - apex) / n1.dot(r1), t2 = n2.dot(tr - apex) / n2.dot(r2);
  if (t1 > 0.0 && t2 > 0.0) {  // beyond the apex
    sigma = apex;
    ds.setZero();
    return Region::Apex;
  }
  const bool compression = plane[1] > plane[0];  // the plane return crossed sigma_1 = sigma_2
  const Eigen::Vector3d& r = compression ? r1 : r2;
  const Eigen::Vector3d& n = compression ? n1 : n2;
  const double t = compression ? t1 : t2;
  if (t > 0.0) {
    sigma = apex;
    ds.setZero();
    return Region::Apex;
  }
  sigma = apex + t * r;
  ds = r * n.transpose() / n.dot(r);
  return compression ? Region::EdgeCompression : Region::EdgeExtension;
}

void MohrCoulomb::update(const Mat3& dF, const double* state_n, double* state, MaterialResponse& out) const {
  const ElasticTrial trial = elastic_trial(dF, unpack_symmetric(state_n));
  const Eigen::Vector3d eps_tr = trial.log_strain();
  const Eigen::Vector3d tr = D_ * eps_tr;  // principal trial Kirchhoff stresses, ascending
  Eigen::Vector3d sorted;
  Mat3 ds;
  const Region reg = return_map(descending(tr), sorted, ds);
  const Eigen::Vector3d tau = descending(sorted);
  const Eigen::Vector3d eps_e = D_.inverse() * tau, d_eps_p = eps_tr - eps_e;
  finish_update(trial, tau, eps_e, state_n[kKappa] + std::sqrt(2.0 / 3.0) * d_eps_p.norm(),
                {static_cast<double>(static_cast<int>(reg))}, state, out);
}

void MohrCoulomb::tangent(const MaterialResponse& r, int dim, Mat9& A) const {
  const ElasticTrial trial = load_trial(r);
  const Eigen::Vector3d eps = trial.log_strain();
  Eigen::Vector3d sorted;
  Mat3 ds;
  return_map(descending(D_ * eps), sorted, ds);
  // D_ab = d tau_a / d eps_b in Eigen's (ascending) order: reverse both indices.
  Mat3 D;
  const Mat3 Ds = ds * D_;  // sorted order
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) D(a, b) = Ds(2 - a, 2 - b);
  const Eigen::Vector3d tau = descending(sorted);
  // c_ab = (tau_a - tau_b) / (l_a - l_b) = [(tau_a - tau_b) / (eps_a - eps_b)] theta_ab / 2,
  // the bracket tending to D_aa - D_ab when eps_a = eps_b.
  const Eigen::Vector3d& l = trial.stretch2;
  Eigen::Vector3d spin;
  const int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (int k = 0; k < 3; ++k) {
    const int a = pairs[k][0], b = pairs[k][1];
    const double de = eps[a] - eps[b];
    const double slope = std::abs(de) > 1e-10 ? (tau[a] - tau[b]) / de : D(a, a) - D(a, b);
    spin[k] = 0.5 * slope * log_divided_difference(l[a], l[b]);
  }
  spectral_tangent(trial, tau, 0.0, D, spin, dim, A);
}

MaterialInfo mohr_coulomb_info() {
  std::vector<KeySpec> keys = isotropic_elasticity_keys();
  // A table of keys (laid out by hand).
  // clang-format off
  keys.push_back({.name = "cohesion", .type = KeyType::Number, .min = 0.0, .min_open = true, .allowed = "a cohesion > 0", .doc = "c"});
  keys.push_back({.name = "friction_angle", .type = KeyType::Number, .min = 0.0, .max = 90.0, .min_open = true, .max_open = true,
                  .allowed = "an angle in degrees in (0, 90)", .doc = "phi, degrees"});
  keys.push_back({.name = "dilation_angle", .type = KeyType::Number, .min = 0.0, .max = 90.0, .max_open = true,
                  .allowed = "an angle in degrees in [0, friction_angle]", .doc = "psi, degrees; psi < phi: non-associated flow, non-symmetric tangent"});
  // clang-format on
  return {
      "mohr-coulomb", "finite-strain Mohr-Coulomb elasto-plasticity, perfectly plastic, non-associated", keys,
      [](const CaseFile& cf, const std::string& prefix, const MaterialInfo& self) -> std::shared_ptr<const Material> {
        const LawKeys in{cf, prefix, self};
        const MohrCoulombParameters p{in.number("cohesion"), in.number("friction_angle"), in.number("dilation_angle")};
        in.require(p.dilation_angle <= p.friction_angle, "dilation_angle", in.spec("dilation_angle").expected());
        const ElasticSolid s = read_elastic_solid(cf, prefix, self);
        return std::make_shared<MohrCoulomb>(s.elasticity, s.density, p);
      }};
}

}  // namespace gradmpm
