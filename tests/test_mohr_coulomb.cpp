// Requirements on Mohr-Coulomb's softening and tension cut-off (materials/MohrCoulomb.hpp):
//  R1 with a softening cohesion the return ends on the surface of the softened strength:
//     f(sigma, kappa) = 0 to 1e-10 sigma_c with kappa = kappa_n + sqrt(2/3) |d eps_p| the
//     new state, on the plane, both edges and the apex, associated and not, and at the
//     residual cohesion once softening passes it within the step;
//  R2 with a tension cut-off every return of the cut-off is reached (its plane sigma_1 =
//     sigma_t, its edge sigma_1 = sigma_2 = sigma_t, its apex, and the corner where it
//     meets Mohr-Coulomb's plane) and lies there to 1e-10, inside both surfaces;
//  R3 the tangent equals central differences of the update (1e-6 relative) in every one of
//     these states;
//  R4 the keys are read and checked: residual_cohesion <= cohesion, tension_cutoff >= 0;
//  R5 phi = psi = 0 is Tresca: sigma_1 - sigma_3 = 2 c on the plane and both edges (1e-10),
//     the mean stress the trial's (deviatoric flow), no apex (a trial of any pressure,
//     however large, stays elastic), the tangent equals central differences.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <iostream>
#include <numbers>
#include <string>
#include <vector>

#include "MaterialTestUtil.hpp"
#include "MpmTestUtil.hpp"
#include "gradmpm/materials/MohrCoulomb.hpp"

using namespace gradmpm;

namespace {
constexpr double kE = 1000.0, kNu = 0.3, kC = 5.0;

std::vector<double> state(double kappa) {
  std::vector<double> s(7, 0.0);
  s[6] = kappa;
  return s;
}
using test::sorted_principal;
using test::stretch;
/// max |A - A_fd| / max |A| at this state.
double tangent_error(const MohrCoulomb& m, const Mat3& dF, const std::vector<double>& st) {
  const Mat9 A = test::tangent_of(m, dF, st);
  const Mat9 Afd = test::finite_difference_tangent(m, dF, st, 1e-8);
  return (A - Afd).cwiseAbs().maxCoeff() / A.cwiseAbs().maxCoeff();
}
}  // namespace

TEST(MohrCoulombSoftening, ReturnsEndOnTheSoftenedSurface) {
  using R = MohrCoulomb::Region;
  struct Case {
    const char* what;
    Eigen::Vector3d eps;
    R expected;
    bool floor;  ///< ends at the residual cohesion
  };
  const std::vector<Case> cases = {
      {"plane", {0.01, 0.0, -0.01}, R::Plane, false},
      {"edge sigma_1 = sigma_2", {0.01, 0.0102, -0.03}, R::EdgeCompression, false},
      {"edge sigma_2 = sigma_3", {0.02, -0.02, -0.0202}, R::EdgeExtension, false},
      {"apex", {0.03, 0.03, 0.03}, R::Apex, false},
      {"plane, past the residual cohesion", {0.12, 0.0, -0.12}, R::Plane, true},
  };
  for (double psi : {30.0, 10.0}) {
    const MohrCoulomb m(IsotropicElasticity(kE, kNu), 1.0, {kC, 30.0, psi, -40.0, 2.0});
    for (const auto& c : cases) {
      const double kappa_n = 0.01;
      const auto u = test::respond(m, stretch(c.eps), state(kappa_n));
      EXPECT_EQ(MohrCoulomb::region(u.r), c.expected) << c.what << ", psi = " << psi;
      const double kappa = u.state[6];
      // kappa = kappa_n + sqrt(2/3) |d eps_p|, d eps_p = eps_trial - eps_e (from eps_n = 0).
      const Eigen::Vector3d eps_e = sorted_principal(unpack_symmetric(u.state.data()));
      Eigen::Vector3d trial = c.eps;
      std::sort(trial.data(), trial.data() + 3, std::greater<>());
      EXPECT_NEAR(kappa, kappa_n + std::sqrt(2.0 / 3.0) * (trial - eps_e).norm(), 1e-12) << c.what;
      const double sc = m.strength(kappa);
      EXPECT_NEAR(m.yield(sorted_principal(u.r.stress), kappa), 0.0, 1e-10 * sc) << c.what << ", psi = " << psi;
      EXPECT_LT(sc, m.strength(kappa_n)) << c.what << ": softened";
      const double residual = m.strength(0.0) / kC * 2.0;  // 2 sqrt(k) c_res, c_res = 2
      if (c.floor) EXPECT_NEAR(sc, residual, 1e-12 * sc) << c.what;
      const double err = tangent_error(m, stretch(c.eps), state(kappa_n));
      std::cout << "softening Mohr-Coulomb, psi = " << psi << ", " << c.what << ": kappa " << kappa << ", sigma_c "
                << sc << ", max |A - A_fd| / max |A| = " << err << "\n";
      EXPECT_LT(err, 1e-6) << c.what << ", psi = " << psi;
    }
  }
}

TEST(MohrCoulombCutoff, EveryReturnOfTheCutoffIsReachedAndLiesThere) {
  const double sigma_t = 1.0;
  struct Case {
    const char* what;
    Eigen::Vector3d eps;
    int at_cutoff;      ///< principal stresses returned to sigma_t
    bool mohr_coulomb;  ///< on Mohr-Coulomb's plane too
  };
  const std::vector<Case> cases = {
      {"cut-off plane", {0.004, -0.002, -0.003}, 1, false},
      {"cut-off edge", {0.004, 0.0038, -0.003}, 2, false},
      {"cut-off apex", {0.01, 0.01, 0.01}, 3, false},
      {"cut-off and Mohr-Coulomb", {0.02, 0.0, -0.015}, 1, true},
  };
  for (double psi : {30.0, 10.0}) {
    const MohrCoulomb m(IsotropicElasticity(kE, kNu), 1.0, {kC, 30.0, psi, 0.0, 0.0, sigma_t});
    const double sc = m.strength(0.0), tol = 1e-10 * sc;
    for (const auto& c : cases) {
      const auto u = test::respond(m, stretch(c.eps), state(0.0));
      EXPECT_EQ(MohrCoulomb::region(u.r), MohrCoulomb::Region::Tension) << c.what;
      const Eigen::Vector3d s = sorted_principal(u.r.stress);
      int at = 0;
      for (int i = 0; i < 3; ++i) at += std::abs(s[i] - sigma_t) < tol;
      EXPECT_EQ(at, c.at_cutoff) << c.what << ", psi = " << psi << ": " << s.transpose();
      EXPECT_LE(s[0], sigma_t + tol) << c.what;
      const double f = m.yield(s);
      EXPECT_LE(f, tol) << c.what;
      if (c.mohr_coulomb)
        EXPECT_NEAR(f, 0.0, tol) << c.what;
      else
        EXPECT_LT(f, -tol) << c.what;
      EXPECT_GT(u.state[6], 0.0) << c.what;
      const double err = tangent_error(m, stretch(c.eps), state(0.0));
      std::cout << "Mohr-Coulomb with a cut-off, psi = " << psi << ", " << c.what << ": sigma " << s.transpose()
                << ", max |A - A_fd| / max |A| = " << err << "\n";
      EXPECT_LT(err, 1e-6) << c.what << ", psi = " << psi;
    }
  }
}

TEST(MohrCoulombTresca, ZeroFrictionIsTrescasPrism) {
  using R = MohrCoulomb::Region;
  const MohrCoulomb m(IsotropicElasticity(kE, kNu), 1.0, {kC, 0.0, 0.0});
  const double tol = 1e-10 * kC;
  struct Case {
    const char* what;
    Eigen::Vector3d eps;
    R expected;
  };
  const std::vector<Case> cases = {
      {"plane", {0.01, 0.0, -0.01}, R::Plane},
      {"edge sigma_1 = sigma_2", {0.01, 0.0102, -0.03}, R::EdgeCompression},
      {"edge sigma_2 = sigma_3", {0.02, -0.02, -0.0202}, R::EdgeExtension},
      {"plane, under a pressure", {-0.09, -0.1, -0.11}, R::Plane},
      {"hydrostatic tension", {0.3, 0.3, 0.3}, R::Elastic},
      {"hydrostatic compression", {-0.3, -0.3, -0.3}, R::Elastic},
  };
  for (const auto& c : cases) {
    const auto u = test::respond(m, stretch(c.eps), state(0.0));
    EXPECT_EQ(MohrCoulomb::region(u.r), c.expected) << c.what;
    const Eigen::Vector3d sg = sorted_principal(u.r.stress);
    // The trial's mean Kirchhoff stress: K tr(log strain) (from eps_n = 0).
    const double bulk = kE / (3.0 * (1.0 - 2.0 * kNu));
    EXPECT_NEAR(sg.mean(), bulk * c.eps.sum(), 1e-10 * std::abs(bulk * c.eps.sum()) + tol) << c.what;
    if (c.expected == R::Elastic) {
      EXPECT_EQ(u.state[6], 0.0) << c.what;
      continue;
    }
    EXPECT_NEAR(sg[0] - sg[2], 2.0 * kC, tol) << c.what;
    if (c.expected == R::EdgeCompression) EXPECT_NEAR(sg[0], sg[1], tol) << c.what;
    if (c.expected == R::EdgeExtension) EXPECT_NEAR(sg[1], sg[2], tol) << c.what;
    const double err = tangent_error(m, stretch(c.eps), state(0.0));
    std::cout << "Tresca, " << c.what << ": sigma " << sg.transpose() << ", max |A - A_fd| / max |A| = " << err << "\n";
    EXPECT_LT(err, 1e-6) << c.what;
  }
}

TEST(MohrCoulombKeys, SofteningAndCutoffAreReadAndChecked) {
  const std::string base =
      "[grid]\norigin=[0.0,0.0]\ncell_size=1.0\ncells=[2,2]\n[materials.a]\nmodel=\"mohr-coulomb\"\nyoung=1000.0\n"
      "cohesion=5.0\nfriction_angle=30.0\ndilation_angle=10.0\n"
      "[[bodies]]\nmaterial=\"a\"\nmin=[0.0,0.0]\nmax=[1.0,1.0]\n[load_steps]\ncount=1\n";
  EXPECT_EQ(test::read_error<2>(CaseFile::parse(
                base, "mc.toml",
                {"materials.a.hardening=-10", "materials.a.residual_cohesion=1", "materials.a.tension_cutoff=0.5"})),
            "");
  const std::string high = test::read_error<2>(CaseFile::parse(base, "mc.toml", {"materials.a.residual_cohesion=6"}));
  EXPECT_NE(high.find("materials.a.residual_cohesion"), std::string::npos) << high;
  const std::string negative = test::read_error<2>(CaseFile::parse(base, "mc.toml", {"materials.a.tension_cutoff=-1"}));
  EXPECT_NE(negative.find("materials.a.tension_cutoff"), std::string::npos) << negative;
}
