// Requirements of the foundation issue on the bi-material bar (paper, Figure 2):
//  R1 the classical FEM solution is exact at the nodes (uniform stress delta/(a/E1+b/E2));
//  R2 u-RA (Dirichlet ends) and e-RA (natural ends) give the closed-form gradient strain,
//     relative error < 1e-4 at x = 0, 2.5, 5, 7.5, 10 on a fine mesh;
//  R3 the strain jump at x = 5 disappears under refinement (and the classical one does not);
//  R4 the total elongation is preserved: u_g(L) = delta for every variant;
//  R5 the gradient step is integrated exactly by the points: 2, 3 or 4 Gauss points give
//     the same answer.
#include <gtest/gtest.h>

#include <iostream>

#include "BarTestUtil.hpp"

using namespace gradmpm;
using namespace gradmpm::test;

TEST(BarClassical, NodallyExact) {
  const BarConfig c = paper_bar(GradientVariant::None, 40);
  const BarResult r = solve_bar(c);
  const auto bar = closed_form(c);
  EXPECT_NEAR(bar.classical_stress(), 0.1 / (5.0 / 1000 + 5.0 / 5000), 1e-12);
  for (std::size_t i = 0; i < r.x.size(); ++i) EXPECT_NEAR(r.u_classical[i], bar.classical_displacement(r.x[i]), 1e-14);
  for (int p = 0; p < r.points.size(); ++p) EXPECT_NEAR(r.point_stress_classical[p], bar.classical_stress(), 1e-10);
}

class BarGradient : public ::testing::TestWithParam<GradientVariant> {};

TEST_P(BarGradient, MatchesClosedFormAtFivePoints) {
  const BarConfig c = paper_bar(GetParam(), 640);
  const BarResult r = solve_bar(c);
  const auto bar = closed_form(c);
  for (double x : {0.0, 2.5, 5.0, 7.5, 10.0}) {
    const double exact = bar.gradient_strain(x, c.length_scale);
    const double got = r.strain_gradient[node_at(c, x)];
    std::cout << to_string(c.variant) << "  x = " << x << "  strain " << got << "  closed form " << exact
              << "  rel. error " << std::abs(got - exact) / exact << "\n";
    EXPECT_LT(std::abs(got - exact) / exact, 1e-4) << "at x = " << x;
  }
}

TEST_P(BarGradient, StrainJumpVanishesUnderRefinement) {
  const auto bar = closed_form(paper_bar(GetParam(), 10));
  const double classical_jump = bar.classical_strain(4.999) - bar.classical_strain(5.001);
  double previous = 0;
  for (int n : {40, 80, 160, 320, 640}) {
    const BarConfig c = paper_bar(GetParam(), n);
    const BarResult r = solve_bar(c);
    // Strain just left and right of x = 5: the two material points nearest the interface.
    const int left = c.points_per_element * n / 2 - 1, right = left + 1;
    ASSERT_LT(r.points.position[left][0], 5.0);
    ASSERT_GT(r.points.position[right][0], 5.0);
    const double jump = std::abs(r.point_strain_gradient[left] - r.point_strain_gradient[right]);
    const double cjump = r.point_strain_classical[left] - r.point_strain_classical[right];
    std::cout << to_string(c.variant) << "  elements " << n << "  gradient jump " << jump << "  classical jump "
              << cjump << "\n";
    EXPECT_NEAR(cjump, classical_jump, 1e-12) << "the classical jump does not shrink";
    if (previous > 0) EXPECT_NEAR(jump / previous, 0.5, 0.05) << "the gradient jump halves with h";
    previous = jump;
  }
  EXPECT_LT(previous, 0.01 * classical_jump);
}

TEST_P(BarGradient, TotalElongationIsPreserved) {
  const BarConfig c = paper_bar(GetParam(), 80);
  const BarResult r = solve_bar(c);
  EXPECT_NEAR(r.u_gradient[0], 0.0, 1e-15);
  EXPECT_NEAR(r.u_gradient[c.elements], c.end_displacement, 1e-13);
}

TEST_P(BarGradient, PointQuadratureIsExact) {
  BarConfig c = paper_bar(GetParam(), 30);
  const BarResult r2 = solve_bar(c);
  for (int n : {3, 4}) {
    c.points_per_element = n;
    const BarResult rn = solve_bar(c);
    EXPECT_LT((rn.u_gradient - r2.u_gradient).lpNorm<Eigen::Infinity>(), 1e-14);
  }
}

INSTANTIATE_TEST_SUITE_P(Variants, BarGradient, ::testing::Values(GradientVariant::U_RA, GradientVariant::E_RA),
                         [](const auto& info) { return info.param == GradientVariant::U_RA ? "uRA" : "eRA"; });

TEST(BarGradient, URADisplacementMatchesClosedForm) {
  const BarConfig c = paper_bar(GradientVariant::U_RA, 320);
  const BarResult r = solve_bar(c);
  const auto bar = closed_form(c);
  for (std::size_t i = 0; i < r.x.size(); ++i)
    EXPECT_NEAR(r.u_gradient[i], bar.gradient_displacement(r.x[i], c.length_scale), 2e-7);
}
