// Requirements on finite-strain von Mises and Drucker-Prager plasticity
// (materials/VonMises.hpp, materials/DruckerPrager.hpp):
//  R1 after a plastic return the stress is on the yield surface, q(tau) = sigma_y(kappa),
//     to 1e-10 relative, with kappa grown by the plastic multiplier; inside the surface
//     the update is Hencky's;
//  R2 the consistent tangent is the derivative of the update (central differences, 1e-6
//     relative) in elastic and plastic states: hardening, perfect plasticity, softening,
//     at the residual floor and when the floor is reached within the step;
//  R3 the tangent is symmetric (associated flow);
//  R4 homogeneous uniaxial strain (dim = 1) compressed to 40 % logarithmic strain in 40
//     MPM load steps gives the small-strain closed form in Kirchhoff stress and
//     logarithmic strain to 1e-8 relative: slope lambda + 2 mu, yield at
//     |tau_axial - tau_lateral| = sigma_y, then slope K + 4/3 mu H / (3 mu + H) (and the
//     residual plateau when softening);
//  R5 Newton converges quadratically in plastic steps of a non-homogeneous problem (a
//     strip load on a block): residual ratios log r_k+1 / log r_k >= 1.8 once r_k < 1e-3
//     (and r_k+1 above the round-off floor, 1e-12);
//  R6 the law is read from a case file with its own keys and ranges, and eps_p reaches
//     points_final.csv by name;
//  R7 Drucker-Prager: returns end on the cone (Phi = 0 to 1e-10) or at its apex
//     (s = 0, p = xi c / eta), both regions reached; the tangent matches central
//     differences (1e-6) on the cone and at the apex, associated or not, hardening or
//     softening; it is symmetric exactly when psi = phi, and the non-associated law then
//     runs in the MPM through linear_solver.general with quadratic convergence;
//  R8 Mohr-Coulomb: the plane, both edges and the apex are reached and the returned
//     stress lies there (f = 0 and the ordering, sigma_1 = sigma_2 or sigma_2 = sigma_3,
//     or the apex); the tangent matches central differences (1e-6) in every region,
//     associated or not, and is symmetric exactly when psi = phi; non-associated it runs
//     in the MPM through linear_solver.general with quadratic convergence;
//  R9 the yield test is not decided by round-off: a point left on the surface, with
//     f = +-1e-14 of its strength, stays elastic (kappa unchanged, Hencky's stress and
//     tangent) under a rigid rotation, for von Mises, Drucker-Prager and Mohr-Coulomb and
//     its tension cut-off;
//  R10 softening steeper than the elastic stiffness (von Mises H < -3 mu, Drucker-Prager
//     H < -(G + K eta eta_bar) / xi^2) returns onto the residual floor, the one root of the
//     return's equation: consistent (f = 0 at the new kappa, kappa grown) just below and
//     just above that slope, with the tangent equal to central differences.
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <Eigen/Dense>
#include <cmath>
#include <iostream>
#include <numbers>

#include <unistd.h>

#include "CliTestUtil.hpp"
#include "MaterialTestUtil.hpp"
#include "MpmTestUtil.hpp"
#include "PlasticityTestUtil.hpp"
#include "gradmpm/app/MpmCase.hpp"
#include "gradmpm/core/Errors.hpp"
#include "gradmpm/core/SymmetricTensor.hpp"
#include "gradmpm/materials/DruckerPrager.hpp"
#include "gradmpm/materials/Hencky.hpp"
#include "gradmpm/materials/MohrCoulomb.hpp"
#include "gradmpm/materials/VonMises.hpp"
#include "gradmpm/points/Generate.hpp"

using namespace gradmpm;

namespace {

constexpr double kE = 1000.0, kNu = 0.3, kSy = 10.0;

VonMises law(double H, double residual = 0.0) {
  return VonMises(IsotropicElasticity(kE, kNu), 1.0, {kSy, H, residual});
}

std::vector<double> state(const Mat3& eps_e, double kappa) {
  std::vector<double> s(7);
  pack_symmetric(eps_e, s.data());
  s[6] = kappa;
  return s;
}

double mises(const Mat3& tau) {
  const Mat3 s = tau - tau.trace() / 3.0 * Mat3::Identity();
  return std::sqrt(1.5 * (s.array() * s.array()).sum());
}

/// A general 3D increment (rotated, sheared, compressed) that yields from a small history.
Mat3 plastic_increment() {
  Mat3 dF;
  dF << 0.97, 0.03, -0.01, 0.02, 1.02, 0.015, -0.01, 0.01, 0.99;
  return dF;
}
Mat3 history_strain() {
  Mat3 e;
  e << 0.004, 0.001, 0.0, 0.001, -0.003, 0.0005, 0.0, 0.0005, 0.001;
  return e;
}

}  // namespace

TEST(VonMises, PlasticReturnEndsOnTheYieldSurface) {
  for (double H : {200.0, 0.0, -100.0}) {
    const VonMises m = law(H, 2.0);
    const auto u = test::respond(m, plastic_increment(), state(history_strain(), 0.01));
    const double kappa = u.state[6];
    ASSERT_GT(kappa, 0.01) << "the increment is plastic, H = " << H;
    const double q = mises(u.r.stress), sy = m.yield_stress(kappa);
    EXPECT_LT(std::abs(q - sy) / sy, 1e-10) << "H = " << H;
  }
  // Inside the surface: Hencky's update, kappa unchanged.
  const VonMises m = law(0.0);
  Mat3 small = Mat3::Identity();
  small(0, 1) = 1e-4;
  const auto u = test::respond(m, small, state(Mat3::Zero(), 0.0));
  EXPECT_EQ(u.state[6], 0.0);
  EXPECT_LT(mises(u.r.stress), kSy);
}

TEST(VonMises, TangentMatchesFiniteDifferencesInElasticAndPlasticStates) {
  struct Case {
    const char* what;
    double H, residual, kappa_n;
    Mat3 dF;
  };
  Mat3 elastic = Mat3::Identity();
  elastic(0, 1) = 2e-3;
  elastic(1, 1) = 0.999;
  const std::vector<Case> cases = {
      {"elastic", 200.0, 0.0, 0.0, elastic},
      {"hardening", 200.0, 0.0, 0.01, plastic_increment()},
      {"perfectly plastic", 0.0, 0.0, 0.01, plastic_increment()},
      {"softening", -100.0, 2.0, 0.01, plastic_increment()},
      {"at the floor", -100.0, 8.0, 0.05, plastic_increment()},
      {"floor reached in the step", -400.0, 8.0, 0.0, plastic_increment()},
  };
  for (const auto& c : cases) {
    const VonMises m = law(c.H, c.residual);
    const auto s = state(history_strain(), c.kappa_n);
    const Mat9 A = test::tangent_of(m, c.dF, s);
    const Mat9 Afd = test::finite_difference_tangent(m, c.dF, s, 1e-7);
    const double err = (A - Afd).cwiseAbs().maxCoeff() / A.cwiseAbs().maxCoeff();
    std::cout << c.what << ": max |A - A_fd| / max |A| = " << err << "\n";
    EXPECT_LT(err, 1e-6) << c.what;
    const double asym = (A - A.transpose()).cwiseAbs().maxCoeff() / A.cwiseAbs().maxCoeff();
    EXPECT_LT(asym, 1e-12) << c.what << ": associated flow has a symmetric tangent";
    // Plane strain and uniaxial blocks are those of the full tangent.
    for (int dim : {1, 2}) {
      const Mat9 B = test::tangent_of(m, c.dF, s, dim);
      for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j)
          for (int k = 0; k < dim; ++k)
            for (int l = 0; l < dim; ++l)
              EXPECT_NEAR(B(3 * i + j, 3 * k + l), A(3 * i + j, 3 * k + l), 1e-12 * A.cwiseAbs().maxCoeff());
    }
  }
}

namespace {
/// tau_axial and tau_lateral of homogeneous uniaxial strain at logarithmic strain eps < 0.
std::pair<double, double> uniaxial_closed_form(double eps, double H, double residual) {
  const IsotropicElasticity e(kE, kNu);
  const double K = e.lambda + 2.0 * e.mu / 3.0, mu = e.mu, a = std::abs(eps);
  double d = 2.0 * mu * a;  // |tau_axial - tau_lateral|
  if (d > kSy) {
    const double kappa = (2.0 * mu * a - kSy) / (3.0 * mu + H);
    d = kSy + H * kappa;
    if (H < 0.0 && d < residual) d = residual;  // then kappa = (2 mu a - residual) / (3 mu)
  }
  const double p = K * eps;
  return {p - 2.0 / 3.0 * d, p + 1.0 / 3.0 * d};  // compression: tau_axial < tau_lateral
}
}  // namespace

TEST(VonMises, UniaxialStrainToFortyPercentMatchesTheClosedForm) {
  for (const auto& [H, residual] : {std::pair{150.0, 0.0}, std::pair{0.0, 0.0}, std::pair{-60.0, 4.0}}) {
    // One cell, four points: every linear basis reproduces the homogeneous state.
    Model<1> m(Grid<1>(Vec<1>(0.0), Vec<1>(1.0), {1}));
    m.materials.push_back(
        std::make_shared<VonMises>(IsotropicElasticity(kE, kNu), 1.0, VonMisesParameters{kSy, H, residual}));
    add_regular_points<1>(
        m.grid, {0}, {1}, 4, [](const Vec<1>&) { return true; }, 0, 1.0, m.points);
    // The grid node moves; the material's log strain grows by ln(1 + du / h) per step
    // (h = 1): 40 equal increments of -0.01.
    m.constraints = {{0, 0, 0.0}, {1, 0, 40.0 * (std::exp(-0.01) - 1.0)}};
    NewtonSettings s;
    s.load_steps = 40;
    double worst = 0.0, last_eps = 0.0;
    bool yielded = false;
    run_quasi_static<1>(m, s, [&](const Model<1>& mm, const StepInfo&) {
      for (int p = 0; p < mm.points.size(); ++p) {
        const double J = mm.points.F[p].determinant(), eps = std::log(mm.points.F[p](0, 0));
        const auto [ta, tl] = uniaxial_closed_form(eps, H, residual);
        const double tau_a = J * mm.points.stress[p](0, 0), tau_l = J * mm.points.stress[p](1, 1);
        worst = std::max({worst, std::abs(tau_a - ta) / std::abs(ta), std::abs(tau_l - tl) / std::abs(ta)});
        yielded = yielded || mm.points.state_of(p)[6] > 0.0;
        last_eps = eps;
      }
    });
    std::cout << "H = " << H << ", residual " << residual << ": final log strain " << last_eps
              << ", max relative error " << worst << "\n";
    EXPECT_NEAR(last_eps, -0.4, 1e-10);
    EXPECT_TRUE(yielded);
    EXPECT_LT(worst, 1e-8) << "H = " << H;
  }
}

using test::strip_load_case;

TEST(VonMises, NewtonConvergesQuadraticallyInPlasticSteps) {
  CaseFile cf = CaseFile::parse(strip_load_case(), "strip.toml");
  MpmCase<2> c = read_mpm_case<2>(cf);
  test::QuadraticRate rate;
  run_quasi_static<2>(c.model, c.newton, [&](const Model<2>& m, const StepInfo& info) {
    bool plastic = false;
    for (int p = 0; p < m.points.size(); ++p) plastic = plastic || m.points.state_of(p)[6] > 0.0;
    if (!plastic) return;
    const auto& r = info.residuals;
    std::cout << "step " << info.step << " residuals";
    for (double x : r) std::cout << " " << x;
    std::cout << "\n";
    rate.add(r);
  });
  EXPECT_GT(rate.checked, 3) << "plastic steps with iterations to check";
  EXPECT_GE(rate.worst, 1.8) << "quadratic convergence";
}

TEST(VonMises, ReadFromACaseFileWithItsKeysAndWritesEpsP) {
  for (const auto& [set, message] :
       {std::pair{"materials.clay.yield_stress=0", "expected a yield stress > 0"},
        std::pair{"materials.clay.residual_yield_stress=11", "expected a residual yield stress <= yield_stress"},
        std::pair{"materials.clay.cohesion=3", "unknown key"}}) {
    const std::string error = test::read_error<2>(CaseFile::parse(strip_load_case(), "strip.toml", {set}));
    EXPECT_NE(error.find(message), std::string::npos) << set << ": " << error;
  }
  const auto dir = std::filesystem::temp_directory_path() / fmt::format("gradmpm-vm-{}", ::getpid());
  std::filesystem::remove_all(dir);
  CaseFile cf = CaseFile::parse(strip_load_case(), "strip.toml", {"load_steps.count=2"});
  run_mpm_case(cf, dir, true);
  const std::string csv = test::slurp(dir / "points_final.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "id,X,Y,Z,x,y,z,sxx,syy,szz,sxy,syz,sxz,volume,mass,exx,eyy,ezz,exy,eyz,exz,eps_p,dissipation");
  std::filesystem::remove_all(dir);
}

namespace {
DruckerPrager dp(double phi, double psi, double H = 0.0, double residual = 0.0, const char* fit = "plane-strain") {
  return DruckerPrager(IsotropicElasticity(kE, kNu), 1.0, {5.0, phi, psi, fit, H, residual});
}
double dp_yield(const DruckerPrager& m, const Mat3& tau, double kappa) {
  const Mat3 s = tau - tau.trace() / 3.0 * Mat3::Identity();
  return std::sqrt(0.5 * (s.array() * s.array()).sum()) + m.eta() * tau.trace() / 3.0 - m.xi() * m.cohesion(kappa);
}
Mat3 dilating_increment() {  // strong volumetric expansion: the return goes to the apex
  Mat3 dF = 1.03 * Mat3::Identity();
  dF(0, 1) = 0.002;
  return dF;
}
}  // namespace

TEST(DruckerPrager, ReturnsEndOnTheConeOrAtTheApex) {
  for (const auto& [phi, psi] : {std::pair{30.0, 30.0}, std::pair{30.0, 10.0}, std::pair{30.0, 0.0}}) {
    const DruckerPrager m = dp(phi, psi, 50.0);
    const auto cone = test::respond(m, plastic_increment(), state(history_strain(), 0.0));
    ASSERT_GT(cone.state[6], 0.0) << "plastic";
    EXPECT_LT(std::abs(dp_yield(m, cone.r.stress, cone.state[6])), 1e-10 * m.xi() * m.cohesion(0.0))
        << phi << "/" << psi;
    const auto apex = test::respond(m, dilating_increment(), state(Mat3::Zero(), 0.0));
    const Mat3 s = apex.r.stress - apex.r.stress.trace() / 3.0 * Mat3::Identity();
    EXPECT_LT(s.norm(), 1e-10 * m.cohesion(0.0)) << "at the apex the deviator vanishes";
    EXPECT_NEAR(apex.r.stress.trace() / 3.0, m.xi() / m.eta() * m.cohesion(apex.state[6]), 1e-10 * m.cohesion(0.0));
    if (psi > 0.0) EXPECT_GT(apex.state[6], 0.0) << "plastic volume change hardens";
  }
  for (const char* fit : {"outer", "inner"}) {  // the Mohr-Coulomb fits: eta = 6 sin phi / (sqrt 3 (3 -+ sin phi))
    const double s = std::sin(30.0 * std::numbers::pi / 180.0);
    const double expected = 6.0 * s / (std::sqrt(3.0) * (std::string(fit) == "outer" ? 3.0 - s : 3.0 + s));
    EXPECT_NEAR(dp(30.0, 30.0, 0.0, 0.0, fit).eta(), expected, 1e-15) << fit;
  }
}

TEST(DruckerPrager, TangentMatchesFiniteDifferencesOnTheConeAndAtTheApex) {
  struct Case {
    const char* what;
    double phi, psi, H, residual, kappa_n;
    Mat3 dF, eps_n;
  };
  const std::vector<Case> cases = {
      {"cone, associated", 30.0, 30.0, 0.0, 0.0, 0.0, plastic_increment(), history_strain()},
      {"cone, psi = 10", 30.0, 10.0, 80.0, 0.0, 0.0, plastic_increment(), history_strain()},
      {"cone, psi = 0, softening", 30.0, 0.0, -20.0, 1.0, 0.01, plastic_increment(), history_strain()},
      {"apex, associated, hardening", 30.0, 30.0, 80.0, 0.0, 0.0, dilating_increment(), Mat3::Zero()},
      {"apex, psi = 15", 30.0, 15.0, 0.0, 0.0, 0.0, dilating_increment(), Mat3::Zero()},
  };
  for (const auto& c : cases) {
    const DruckerPrager m = dp(c.phi, c.psi, c.H, c.residual);
    const auto s = state(c.eps_n, c.kappa_n);
    const Mat9 A = test::tangent_of(m, c.dF, s);
    const Mat9 Afd = test::finite_difference_tangent(m, c.dF, s, 1e-7);
    const double err = (A - Afd).cwiseAbs().maxCoeff() / A.cwiseAbs().maxCoeff();
    const double asym = (A - A.transpose()).cwiseAbs().maxCoeff() / A.cwiseAbs().maxCoeff();
    std::cout << c.what << ": max |A - A_fd| / max |A| = " << err << ", asymmetry " << asym << "\n";
    EXPECT_LT(err, 1e-6) << c.what;
    EXPECT_EQ(m.symmetric_tangent(), c.psi == c.phi);
    if (c.psi == c.phi)
      EXPECT_LT(asym, 1e-12) << c.what;
    else if (std::string(c.what).rfind("cone", 0) == 0)
      EXPECT_GT(asym, 1e-3) << c.what << ": non-associated flow on the cone";
  }
}

class NonAssociated : public ::testing::TestWithParam<const char*> {};
INSTANTIATE_TEST_SUITE_P(Plasticity, NonAssociated, ::testing::Values("drucker-prager", "mohr-coulomb"));

TEST_P(NonAssociated, LawRunsThroughTheGeneralSolverWithQuadraticConvergence) {
  CaseFile cf = CaseFile::parse(strip_load_case(std::string("model = \"") + GetParam() +
                                                "\"\nyoung = 1000.0\npoisson = 0.3\ncohesion = 4.0\n"
                                                "friction_angle = 25.0\ndilation_angle = 0.0\n"),
                                "strip.toml");
  MpmCase<2> c = read_mpm_case<2>(cf);
  ASSERT_FALSE(c.model.symmetric_tangent());
  test::QuadraticRate rate;
  run_quasi_static<2>(c.model, c.newton, [&](const Model<2>&, const StepInfo& info) { rate.add(info.residuals); });
  double kappa = 0.0;
  for (int p = 0; p < c.model.points.size(); ++p) kappa = std::max(kappa, c.model.points.state_of(p)[6]);
  std::cout << "non-associated " << GetParam() << " strip load: max eps_p " << kappa << ", worst log-ratio "
            << rate.worst << " over " << rate.checked << " iterations\n";
  EXPECT_GT(kappa, 0.0);
  EXPECT_GT(rate.checked, 3);
  EXPECT_GE(rate.worst, 1.8);
}

namespace {
MohrCoulomb mc(double phi, double psi) { return MohrCoulomb(IsotropicElasticity(kE, kNu), 1.0, {5.0, phi, psi}); }
using test::sorted_principal;
using test::stretch;
}  // namespace

TEST(MohrCoulomb, EveryRegionIsReachedAndItsReturnLiesThere) {
  using R = MohrCoulomb::Region;
  struct Case {
    const char* what;
    Eigen::Vector3d eps;
    R expected;
  };
  const std::vector<Case> cases = {
      {"elastic", {0.001, 0.0, -0.001}, R::Elastic},
      {"plane", {0.01, 0.0, -0.01}, R::Plane},
      {"edge sigma_1 = sigma_2 (triaxial compression)", {0.01, 0.0102, -0.03}, R::EdgeCompression},
      {"edge sigma_2 = sigma_3 (triaxial extension)", {0.02, -0.02, -0.0202}, R::EdgeExtension},
      {"apex", {0.03, 0.03, 0.03}, R::Apex},
  };
  for (const auto& [phi, psi] : {std::pair{30.0, 30.0}, std::pair{30.0, 10.0}}) {
    const MohrCoulomb m = mc(phi, psi);
    const double s = std::sin(phi * std::numbers::pi / 180.0), k = (1 + s) / (1 - s);
    const double sigma_c = 2.0 * 5.0 * std::cos(phi * std::numbers::pi / 180.0) / (1 - s), apex = sigma_c / (k - 1);
    for (const auto& c : cases) {
      const auto u = test::respond(m, stretch(c.eps), state(Mat3::Zero(), 0.0));
      EXPECT_EQ(MohrCoulomb::region(u.r), c.expected) << c.what << ", psi = " << psi;
      const Eigen::Vector3d sg = sorted_principal(u.r.stress);
      const double tol = 1e-10 * sigma_c;
      if (c.expected != R::Elastic) EXPECT_NEAR(m.yield(sg), 0.0, tol) << c.what;
      EXPECT_GE(sg[0], sg[1] - tol);
      EXPECT_GE(sg[1], sg[2] - tol);
      if (c.expected == R::EdgeCompression) EXPECT_NEAR(sg[0], sg[1], tol) << c.what;
      if (c.expected == R::EdgeExtension) EXPECT_NEAR(sg[1], sg[2], tol) << c.what;
      if (c.expected == R::Apex) EXPECT_LT((sg - apex * Eigen::Vector3d::Ones()).norm(), tol) << c.what;
      if (c.expected != R::Elastic) EXPECT_GT(u.state[6], 0.0) << c.what;
      // The tangent in this region against central differences.
      const auto st = state(Mat3::Zero(), 0.0);
      const Mat9 A = test::tangent_of(m, stretch(c.eps), st);
      const Mat9 Afd = test::finite_difference_tangent(m, stretch(c.eps), st, 1e-8);
      const double scale = A.cwiseAbs().maxCoeff();
      const double err = (A - Afd).cwiseAbs().maxCoeff() / scale;
      const double asym = (A - A.transpose()).cwiseAbs().maxCoeff() / scale;
      std::cout << "Mohr-Coulomb, psi = " << psi << ", " << c.what << ": max |A - A_fd| / max |A| = " << err
                << ", asymmetry " << asym << "\n";
      EXPECT_LT(err, 1e-6) << c.what << ", psi = " << psi;
      if (psi == phi || c.expected == R::Elastic || c.expected == R::Apex)
        EXPECT_LT(asym, 1e-10) << c.what;
      else
        EXPECT_GT(asym, 1e-4) << c.what << ": non-associated";
    }
    EXPECT_EQ(m.symmetric_tangent(), psi == phi);
  }
}

namespace {
/// A small rigid rotation: a load step that changes no strain.
Mat3 rotation() { return Eigen::AngleAxisd(0.1, Eigen::Vector3d(1.0, 2.0, 3.0).normalized()).toRotationMatrix(); }
/// The elastic state with deviatoric principal strains (a, -a, 0) in a rotated frame.
std::vector<double> deviatoric_state(double a, std::size_t size = 7) {
  std::vector<double> st(size, 0.0);
  const Mat3 Q = rotation().transpose();
  pack_symmetric(Q * Eigen::Vector3d(a, -a, 0.0).asDiagonal() * Q.transpose(), st.data());
  return st;
}
/// Checks that `m`, from eps_n (kappa_n = 0), rotated rigidly stays elastic: kappa stays 0
/// and the stress and tangent are Hencky's.
void expect_elastic(const Material& m, const std::vector<double>& st, const std::string& what) {
  const Hencky hencky(kE, kNu, 1.0);
  const std::vector<double> eps_n(st.begin(), st.begin() + 6);
  const auto u = test::respond(m, rotation(), st);
  const auto h = test::respond(hencky, rotation(), eps_n);
  EXPECT_EQ(u.state[6], 0.0) << what << ": kappa unchanged";
  EXPECT_LT((u.r.stress - h.r.stress).norm(), 1e-12 * h.r.stress.norm()) << what;
  const Mat9 A = test::tangent_of(m, rotation(), st), Ah = test::tangent_of(hencky, rotation(), eps_n);
  EXPECT_LT((A - Ah).cwiseAbs().maxCoeff(), 1e-10 * Ah.cwiseAbs().maxCoeff()) << what << ": the elastic tangent";
}
}  // namespace

TEST(YieldTest, APointOnTheSurfaceWithinRoundOffStaysElastic) {
  const double mu = IsotropicElasticity(kE, kNu).mu;
  for (double delta : {1e-14, -1e-14}) {
    const std::string d = fmt::format(", f = {:g} of the strength", delta);
    // von Mises: q = 2 sqrt(3) mu a.
    expect_elastic(law(0.0), deviatoric_state(kSy * (1.0 + delta) / (2.0 * std::sqrt(3.0) * mu)), "von Mises" + d);
    // Drucker-Prager at p = 0: sqrt(J2) = 2 mu a = xi c.
    const DruckerPrager cone = dp(30.0, 30.0);
    expect_elastic(cone, deviatoric_state(cone.xi() * cone.cohesion(0.0) * (1.0 + delta) / (2.0 * mu)),
                   "Drucker-Prager" + d);
    // Mohr-Coulomb's plane: k sigma_1 - sigma_3 = 2 mu a (k + 1) = 2 sqrt(k) c.
    const double sn = std::sin(30.0 * std::numbers::pi / 180.0), k = (1.0 + sn) / (1.0 - sn);
    expect_elastic(mc(30.0, 30.0), deviatoric_state(2.0 * std::sqrt(k) * 5.0 * (1.0 + delta) / (2.0 * mu * (k + 1.0))),
                   "Mohr-Coulomb" + d);
    // The tension cut-off sigma_t = 1: uniaxial strain b gives sigma_1 = (lambda + 2 mu) b.
    const IsotropicElasticity e(kE, kNu);
    const MohrCoulomb cutoff(e, 1.0, {5.0, 30.0, 30.0, 0.0, 0.0, 1.0});
    std::vector<double> st(7, 0.0);
    const Mat3 Q = rotation().transpose();
    const double b = (1.0 + delta) / (e.lambda + 2.0 * e.mu);
    pack_symmetric(Q * Eigen::Vector3d(b, 0.0, 0.0).asDiagonal() * Q.transpose(), st.data());
    expect_elastic(cutoff, st, "Mohr-Coulomb's tension cut-off" + d);
  }
}

TEST(SteepSoftening, ReturnsOntoTheResidualFloorJustBelowAndAboveTheElasticStiffness) {
  const IsotropicElasticity e(kE, kNu);
  const double K = e.lambda + 2.0 * e.mu / 3.0;
  for (double factor : {1.01, 0.99, 0.9999}) {
    // von Mises from a state at its strength (kappa_n = 0.001): H = -factor 3 mu.
    const VonMises m = law(-factor * 3.0 * e.mu, 2.0);
    const auto st = state(history_strain(), 0.001);
    const auto u = test::respond(m, plastic_increment(), st);
    const double kappa = u.state[6], q = mises(u.r.stress), sy = m.yield_stress(kappa);
    std::cout << "von Mises, H = " << -factor << " x 3 mu: q = " << q << ", sigma_y(kappa) = " << sy
              << ", kappa = " << kappa << "\n";
    EXPECT_GT(kappa, 0.001) << factor;
    EXPECT_LT(std::abs(q - sy), 1e-10 * kSy) << factor;
    if (factor > 1.0) EXPECT_NEAR(q, 2.0, 1e-10 * kSy) << "on the floor";
    const Mat9 A = test::tangent_of(m, plastic_increment(), st);
    const Mat9 Afd = test::finite_difference_tangent(m, plastic_increment(), st, 1e-7);
    EXPECT_LT((A - Afd).cwiseAbs().maxCoeff() / A.cwiseAbs().maxCoeff(), 1e-6) << factor;

    // Drucker-Prager (associated): the cone's stiffness G + K eta^2 + xi^2 H.
    const DruckerPrager probe = dp(30.0, 30.0);
    const double critical = -(e.mu + K * probe.eta() * probe.eta()) / (probe.xi() * probe.xi());
    const DruckerPrager c = dp(30.0, 30.0, factor * critical, 1.0);
    const auto v = test::respond(c, plastic_increment(), st);
    std::cout << "Drucker-Prager, H = " << factor << " x " << critical
              << ": Phi = " << dp_yield(c, v.r.stress, v.state[6]) << ", c(kappa) = " << c.cohesion(v.state[6]) << "\n";
    EXPECT_GT(v.state[6], 0.001) << factor;
    EXPECT_LT(std::abs(dp_yield(c, v.r.stress, v.state[6])), 1e-10 * c.xi() * 5.0) << factor;
    if (factor > 1.0) EXPECT_EQ(c.cohesion(v.state[6]), 1.0) << "on the floor";
    const Mat9 B = test::tangent_of(c, plastic_increment(), st);
    const Mat9 Bfd = test::finite_difference_tangent(c, plastic_increment(), st, 1e-7);
    EXPECT_LT((B - Bfd).cwiseAbs().maxCoeff() / B.cwiseAbs().maxCoeff(), 1e-6) << factor;
  }
}
