// Requirements of Modified Cam-Clay (materials/ModifiedCamClay.hpp, docs/pore-pressure.md):
//   M1 after a return the stress lies on the yield surface q^2 / M^2 + P (P - P_c) = 0 to
//      1e-10 P_c^2, with P_c the hardened preconsolidation pressure of the new state;
//   M2 the consistent tangent equals the central differences of the update (elastic and
//      plastic, normally and lightly overconsolidated, after earlier plastic strain) to
//      1e-5 of its largest entry; it is symmetric where the step is elastic only (the
//      hardening by eps_v^p is not associated with P_c: the law declares it non-symmetric);
//   M3 drained triaxial compression of normally consolidated clay (radial stress held at
//      p_0): the volume change follows the model's closed form
//      eps_v = kappa~ ln(P / p_0) + (lambda~ - kappa~) ln(P_c / p_c0), P_c = P + q^2 / (M^2 P),
//      to 1e-9, and the path ends at the critical state q = M P, P = 3 p_0 / (3 - M);
//   M4 undrained (isochoric) triaxial compression of normally consolidated clay follows the
//      closed-form effective stress path q = M P sqrt((p_0 / P)^(1 / Lambda) - 1),
//      Lambda = (lambda - kappa) / lambda, to 1e-8 p_0, and fails at P = p_0 2^-Lambda
//      (Wood 1990, ch. 6).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "MaterialTestUtil.hpp"
#include "gradmpm/materials/ModifiedCamClay.hpp"

using namespace gradmpm;
using namespace gradmpm::test;

namespace {

CamClayParameters clay(double ocr = 1.0) {
  CamClayParameters p;
  p.lambda = 0.2;
  p.kappa = 0.04;
  p.M = 1.2;
  p.e0 = 1.0;
  p.p0 = 100e3;
  p.pc0 = ocr * p.p0;
  p.shear_modulus = ModifiedCamClay::shear_modulus_of(0.3, p.p0, p.kappa, p.e0);
  return p;
}

struct Invariants {
  double P, q;
};
Invariants invariants(const Mat3& tau) {
  const double P = -tau.trace() / 3.0;
  const Mat3 s = tau + P * Mat3::Identity();
  return {P, std::sqrt(1.5) * s.norm()};
}

std::vector<double> fresh_state(const Material& m) {
  std::vector<double> s(m.state_size());
  m.initial_state(s.data());
  return s;
}

/// Principal loading: the axial (z) and radial (x, y) log-strain increments.
Mat3 triaxial(double d_axial, double d_radial) {
  return Eigen::Vector3d(std::exp(d_radial), std::exp(d_radial), std::exp(d_axial)).asDiagonal();
}

}  // namespace

TEST(CamClay, M1_ReturnsLieOnTheHardenedYieldSurface) {
  for (double ocr : {1.0, 1.5}) {
    const ModifiedCamClay m(clay(ocr), 0.0);
    const auto s0 = fresh_state(m);
    double worst = 0.0;
    int plastic = 0;
    for (const Eigen::Vector3d eps : {Eigen::Vector3d(-0.02, 0.005, 0.005), Eigen::Vector3d(-0.05, -0.01, 0.02),
                                      Eigen::Vector3d(-0.03, -0.03, -0.03), Eigen::Vector3d(0.01, -0.04, 0.0),
                                      Eigen::Vector3d(-0.1, 0.04, 0.03)}) {
      const Updated u = respond(m, stretch(eps), s0);
      const auto [P, q] = invariants(u.r.stress);
      const double Pc = m.preconsolidation(u.state[PlasticLaw::kKappa]);
      const double f = q * q / (m.parameters().M * m.parameters().M) + P * (P - Pc);
      if (u.state[PlasticLaw::kKappa] == 0.0) continue;  // (elastic)
      ++plastic;
      worst = std::max(worst, std::abs(f) / (Pc * Pc));
    }
    std::cout << fmt::format("  OCR {}: {} returns, |f| / P_c^2 at most {:.2e}\n", ocr, plastic, worst);
    EXPECT_GE(plastic, 4);
    EXPECT_LT(worst, 1e-10);
  }
}

TEST(CamClay, M2_TheConsistentTangentIsTheUpdatesDerivativeAndSymmetric) {
  struct Case {
    double ocr;
    Eigen::Vector3d before, now;  ///< an earlier step (its state), then this step's principal strains
  };
  const Case cases[] = {{1.0, {0, 0, 0}, {-1e-3, 2e-4, 1e-4}},         // plastic from the tip
                        {1.5, {0, 0, 0}, {-2e-4, 1e-4, 0.0}},          // elastic inside
                        {1.5, {0, 0, 0}, {-0.02, 0.004, 0.003}},       // plastic, overconsolidated
                        {1.0, {-0.03, 0.01, 0.005}, {-0.01, 0.002, 0.003}},  // after plastic strain
                        {1.0, {-0.02, -0.02, -0.02}, {-0.004, 0.001, 0.0}}};
  for (const Case& c : cases) {
    const ModifiedCamClay m(clay(c.ocr), 0.0);
    const std::vector<double> s1 = respond(m, stretch(c.before), fresh_state(m)).state;
    const Mat3 dF = stretch(c.now);
    const Mat9 A = tangent_of(m, dF, s1), Afd = finite_difference_tangent(m, dF, s1, 1e-7);
    const double scale = A.cwiseAbs().maxCoeff();
    const double error = (A - Afd).cwiseAbs().maxCoeff() / scale;
    const double asymmetry = (A - A.transpose()).cwiseAbs().maxCoeff() / scale;  // (A_ijkl = A_klij)
    std::cout << fmt::format("  OCR {} plastic {}: |A - A_fd| / |A| = {:.2e}, |A - A^T| / |A| = {:.2e}\n", c.ocr,
                             respond(m, dF, s1).state[PlasticLaw::kKappa] != s1[PlasticLaw::kKappa], error, asymmetry);
    EXPECT_LT(error, 1e-5);
    const bool plastic = respond(m, dF, s1).state[PlasticLaw::kKappa] != s1[PlasticLaw::kKappa];
    if (!plastic) EXPECT_LT(asymmetry, 1e-12);
    EXPECT_FALSE(m.symmetric_tangent());
  }
}

TEST(CamClay, M3_DrainedTriaxialCompressionFollowsTheClosedFormToCriticalState) {
  const CamClayParameters par = clay();
  const ModifiedCamClay m(par, 0.0);
  std::vector<double> state = fresh_state(m);
  double eps_a = 0.0, eps_r = 0.0, worst = 0.0;
  Invariants last{};
  const double de = -0.002;
  for (int step = 0; step < 400; ++step) {
    // the radial increment that keeps the radial stress at -p_0 (secant iterations)
    double d_r = step == 0 ? 0.3 * -de : 0.0, d_r_old = d_r + 1e-6;
    const auto radial = [&](double dr) { return respond(m, triaxial(de, dr), state).r.stress(0, 0) + par.p0; };
    double g = radial(d_r), g_old = radial(d_r_old);
    for (int it = 0; it < 100 && std::abs(g) > 1e-9 * par.p0; ++it) {
      const double next = d_r - g * (d_r - d_r_old) / (g - g_old);
      d_r_old = d_r, g_old = g;
      d_r = next, g = radial(d_r);
    }
    ASSERT_LT(std::abs(g), 1e-8 * par.p0) << "step " << step;
    const Updated u = respond(m, triaxial(de, d_r), state);
    state = u.state;
    eps_a += de, eps_r += d_r;
    const auto [P, q] = invariants(u.r.stress);
    const double Pc = P + q * q / (par.M * par.M * P);
    const double ev = m.kappa_tilde() * std::log(P / par.p0) + (m.lambda_tilde() - m.kappa_tilde()) * std::log(Pc / par.pc0);
    worst = std::max(worst, std::abs(-(eps_a + 2.0 * eps_r) - ev));
    last = {P, q};
  }
  std::cout << fmt::format("  eps_v off its closed form by at most {:.2e}; at eps_a = {:.2f}: q / P = {:.6f} (M = {}), "
                           "P = {:.1f} (critical state {:.1f})\n",
                           worst, eps_a, last.q / last.P, par.M, last.P, 3.0 * par.p0 / (3.0 - par.M));
  EXPECT_LT(worst, 1e-9);
  EXPECT_NEAR(last.q / last.P, par.M, 1e-3 * par.M);
  EXPECT_NEAR(last.P, 3.0 * par.p0 / (3.0 - par.M), 1e-3 * par.p0);
}

TEST(CamClay, M4_UndrainedTriaxialFollowsTheClosedFormEffectiveStressPath) {
  const CamClayParameters par = clay();
  const ModifiedCamClay m(par, 0.0);
  const double Lambda = (par.lambda - par.kappa) / par.lambda;
  std::vector<double> state = fresh_state(m);
  double worst = 0.0;
  Invariants last{};
  const double de = -0.001;
  for (int step = 0; step < 300; ++step) {
    const Updated u = respond(m, triaxial(de, -0.5 * de), state);  // isochoric
    state = u.state;
    const auto [P, q] = invariants(u.r.stress);
    const double expected = par.M * P * std::sqrt(std::pow(par.p0 / P, 1.0 / Lambda) - 1.0);
    worst = std::max(worst, std::abs(q - expected) / par.p0);
    last = {P, q};
  }
  std::cout << fmt::format("  q off the closed-form path by at most {:.2e} p_0; at the end P = {:.1f} (failure "
                           "{:.1f}), q / P = {:.6f}\n",
                           worst, last.P, par.p0 * std::pow(0.5, Lambda), last.q / last.P);
  EXPECT_LT(worst, 1e-8);
  EXPECT_NEAR(last.P, par.p0 * std::pow(0.5, Lambda), 1e-3 * par.p0);
  EXPECT_NEAR(last.q / last.P, par.M, 1e-3 * par.M);
}
