// Requirements on the gradient operator (M + l^2 L) g = f of the Ru-Aifantis split:
//  - a sinusoid c = cos(kx) (natural ends) or sin(kx) (Dirichlet ends) is an eigenfunction
//    of (1 - l^2 d2/dx2): it must come back damped by exactly 1/(1 + k^2 l^2), with the
//    discretisation error falling at second order in h;
//  - constants are left unchanged (natural boundaries), l = 0 is the L2 projection.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numbers>

#include "gradmpm/basis/LinearBasis.hpp"
#include "gradmpm/gradient/Helmholtz.hpp"
#include "gradmpm/points/Generate.hpp"

using namespace gradmpm;

namespace {
constexpr double kLength = 10.0;

struct Bar1D {
  Grid<1> grid;
  MaterialPoints<1> points;
  PointStencils<1> st;
  DofMap dofs;
  SparseMatrix pattern;
  explicit Bar1D(int elements, int gauss = 2) : grid(Vec<1>(0.0), Vec<1>(kLength / elements), {elements}) {
    add_gauss_points<1>(
        grid, {0}, {elements}, gauss, [](const Vec<1>&) { return 0; }, points);
    st = evaluate_stencils<1, LinearBasis<1>>(grid, points);
    dofs = DofMap(st, grid.num_nodes(), 1);
    pattern = build_pattern(st, dofs);
  }
  std::vector<double> at_points(auto f) const {
    std::vector<double> v;
    for (const auto& x : points.position) v.push_back(f(x[0]));
    return v;
  }
  Vector at_nodes(auto f) const {
    Vector v(grid.num_nodes());
    for (int n = 0; n < grid.num_nodes(); ++n) v[n] = f(grid.node_position(n)[0]);
    return v;
  }
};

/// max_i |g_i - c(x_i)/(1 + k^2 l^2)| / amplitude
double damping_error(int elements, bool dirichlet, double l, int mode) {
  const Bar1D bar(elements);
  const double k = mode * std::numbers::pi / kLength;
  const double damping = 1.0 / (1.0 + k * k * l * l);
  const Assembler<1> as(bar.st, bar.points, bar.dofs);
  Vector g;
  if (dirichlet) {  // u-RA style: sin(kx), ends prescribed (zero)
    const std::vector<int> ends = {bar.dofs.dof(0, 0), bar.dofs.dof(elements, 0)};
    const HelmholtzSmoother<1> sm(as, bar.pattern, l, ends);
    g = sm.smooth_nodal_field(bar.at_nodes([&](double x) { return std::sin(k * x); }), {0.0, 0.0});
    const Vector ref = bar.at_nodes([&](double x) { return damping * std::sin(k * x); });
    return (g - ref).lpNorm<Eigen::Infinity>();
  }
  const HelmholtzSmoother<1> sm(as, bar.pattern, l);  // e-RA style: cos(kx), natural ends
  g = sm.smooth_point_field(bar.at_points([&](double x) { return std::cos(k * x); }));
  const Vector ref = bar.at_nodes([&](double x) { return damping * std::cos(k * x); });
  return (g - ref).lpNorm<Eigen::Infinity>();
}
}  // namespace

class SinusoidDamping : public ::testing::TestWithParam<bool> {};

TEST_P(SinusoidDamping, ExactFactorWithSecondOrderConvergence) {
  const bool dirichlet = GetParam();
  const double l = 2.0;
  for (int mode : {1, 3}) {
    double previous = 0;
    std::cout << (dirichlet ? "sin, Dirichlet ends" : "cos, natural ends") << ", mode " << mode
              << ", damping 1/(1+k^2 l^2) = " << 1.0 / (1.0 + std::pow(mode * std::numbers::pi / kLength * l, 2))
              << "\n";
    for (int n : {20, 40, 80, 160, 320}) {
      const double err = damping_error(n, dirichlet, l, mode);
      std::cout << "  elements " << n << "  max nodal error " << err;
      if (previous > 0) {
        const double rate = std::log2(previous / err);
        std::cout << "  rate " << rate;
        EXPECT_GT(rate, 1.9);
        EXPECT_LT(rate, 2.1);
      }
      std::cout << "\n";
      previous = err;
    }
    EXPECT_LT(previous, 2e-4 * mode * mode) << "the damping factor is reproduced on the finest mesh";
  }
}
INSTANTIATE_TEST_SUITE_P(Helmholtz, SinusoidDamping, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? "DirichletSine" : "NaturalCosine"; });

TEST(Helmholtz, ConstantsAreUnchangedWithNaturalBoundaries) {
  const Bar1D bar(37, 3);
  const Assembler<1> as(bar.st, bar.points, bar.dofs);
  const HelmholtzSmoother<1> sm(as, bar.pattern, 3.0);
  const Vector g = sm.smooth_point_field(bar.at_points([](double) { return 0.125; }));
  EXPECT_LT((g.array() - 0.125).abs().maxCoeff(), 1e-14);
}

TEST(Helmholtz, ZeroLengthScaleIsTheL2Projection) {
  // l = 0 and a field linear in x: the L2 projection onto linear elements returns it exactly.
  const Bar1D bar(16);
  const Assembler<1> as(bar.st, bar.points, bar.dofs);
  const HelmholtzSmoother<1> sm(as, bar.pattern, 0.0);
  const Vector g = sm.smooth_point_field(bar.at_points([](double x) { return 1.0 + 2.0 * x; }));
  const Vector ref = bar.at_nodes([](double x) { return 1.0 + 2.0 * x; });
  EXPECT_LT((g - ref).lpNorm<Eigen::Infinity>(), 1e-12);
}

TEST(Helmholtz, TwoDimensionalOperatorDampsAPlaneWave) {
  // The same templated operator in 2D: c = cos(kx x) cos(ky y) on [0,1]^2 with natural
  // boundaries is damped by 1/(1 + l^2 |k|^2) (up to O(h^2)).
  const int n = 64;
  const Grid<2> grid(Vec<2>(0.0, 0.0), Vec<2>(1.0 / n, 1.0 / n), {n, n});
  MaterialPoints<2> pts;
  add_gauss_points<2>(
      grid, {0, 0}, {n, n}, 2, [](const Vec<2>&) { return 0; }, pts);
  const auto st = evaluate_stencils<2, LinearBasis<2>>(grid, pts);
  const DofMap dofs(st, grid.num_nodes(), 1);
  const SparseMatrix pattern = build_pattern(st, dofs);
  const Assembler<2> as(st, pts, dofs);
  const double l = 0.1, kx = std::numbers::pi, ky = 2 * std::numbers::pi;
  const HelmholtzSmoother<2> sm(as, pattern, l);
  std::vector<double> c;
  for (const auto& x : pts.position) c.push_back(std::cos(kx * x[0]) * std::cos(ky * x[1]));
  const Vector g = sm.smooth_point_field(c);
  const double damping = 1.0 / (1.0 + l * l * (kx * kx + ky * ky));
  double err = 0;
  for (int i = 0; i < grid.num_nodes(); ++i) {
    const Vec<2> x = grid.node_position(i);
    err = std::max(err, std::abs(g[dofs.dof(i, 0)] - damping * std::cos(kx * x[0]) * std::cos(ky * x[1])));
  }
  std::cout << "2D plane wave: damping " << damping << ", max nodal error " << err << " (h = 1/" << n << ")\n";
  EXPECT_LT(err, 2e-3 * damping);
}
