// Requirements on the limits of the gradient variants:
//  R1 l = 0 gives back the classical solution (u-RA exactly);
//  R2 l -> 0 recovers the classical strain for e-RA: the smoothed region shrinks with l
//     (integral of |eps_g - eps_c| = (eps1 - eps2) l for l << L);
//  R3 s-RA leaves the 1D stress constant, so it keeps the strain jump: equilibrium makes
//     the classical stress uniform, and a constant is a fixed point of (1 - l^2 d2/dx2)
//     with natural boundaries;
//  R4 "none" reports the classical fields as the gradient ones.
#include <gtest/gtest.h>

#include <iostream>

#include "BarTestUtil.hpp"

using namespace gradmpm;
using namespace gradmpm::test;

TEST(BarLimits, ZeroLengthScaleURAIsClassical) {
  const BarResult r = solve_bar(paper_bar(GradientVariant::U_RA, 64, 0.0));
  EXPECT_LT((r.u_gradient - r.u_classical).lpNorm<Eigen::Infinity>(), 1e-15);
  for (int p = 0; p < r.points.size(); ++p) EXPECT_NEAR(r.point_strain_gradient[p], r.point_strain_classical[p], 1e-13);
}

TEST(BarLimits, VanishingLengthScaleERAConvergesToClassical) {
  const auto bar = closed_form(paper_bar(GradientVariant::E_RA, 10));
  const double jump = bar.classical_strain(4.0) - bar.classical_strain(6.0);
  double previous = 0;
  for (double l : {0.4, 0.2, 0.1, 0.05}) {
    const int elements = static_cast<int>(std::lround(10.0 / (l / 16)));  // h = l/16
    const BarResult r = solve_bar(paper_bar(GradientVariant::E_RA, elements, l));
    double l1 = 0;  // integral |eps_g - eps_c| over the points
    for (int p = 0; p < r.points.size(); ++p)
      l1 += std::abs(r.point_strain_gradient[p] - r.point_strain_classical[p]) * r.points.volume[p];
    std::cout << "l = " << l << "  integral |eps_g - eps_c| = " << l1 << "  / ((eps1-eps2) l) = " << l1 / (jump * l)
              << "\n";
    EXPECT_NEAR(l1 / (jump * l), 1.0, 0.02);
    if (previous > 0) EXPECT_NEAR(l1 / previous, 0.5, 0.01);
    previous = l1;
  }
}

TEST(BarLimits, SRAKeepsConstantStressAndTheStrainJump) {
  const BarConfig c = paper_bar(GradientVariant::S_RA, 80);
  const BarResult r = solve_bar(c);
  const auto bar = closed_form(c);
  for (int i = 0; i <= c.elements; ++i) EXPECT_NEAR(r.stress_gradient[i], bar.classical_stress(), 1e-10);
  for (int p = 0; p < r.points.size(); ++p) {
    EXPECT_NEAR(r.point_stress_gradient[p], bar.classical_stress(), 1e-10);
    EXPECT_NEAR(r.point_strain_gradient[p], bar.classical_strain(r.points.position[p][0]), 1e-13);
  }
  const int left = c.points_per_element * c.elements / 2 - 1;
  EXPECT_NEAR(r.point_strain_gradient[left] - r.point_strain_gradient[left + 1],
              bar.classical_strain(4.9) - bar.classical_strain(5.1), 1e-13);
}

TEST(BarLimits, NoneReportsClassicalFields) {
  const BarResult r = solve_bar(paper_bar(GradientVariant::None, 20));
  EXPECT_EQ(r.u_gradient, r.u_classical);
  EXPECT_EQ(r.strain_gradient, r.strain_classical);
  EXPECT_EQ(r.stress_gradient, r.stress_classical);
}
