// Requirement: the bi-material bar of the foundation issue run through the MPM driver
// (points at Gauss positions, small-strain linear elasticity) gives the FEM result to
// round-off in one load step, and stays within a documented tolerance with many load
// steps and moving points (the incrementally linear MPM of the paper).
#include <gtest/gtest.h>

#include <iostream>
#include <map>

#include "BarTestUtil.hpp"
#include "gradmpm/materials/Hencky.hpp"
#include "gradmpm/materials/LinearElastic.hpp"
#include "gradmpm/mpm/QuasiStatic.hpp"
#include "gradmpm/points/Generate.hpp"

using namespace gradmpm;
using namespace gradmpm::test;

namespace {
Model<1> bar_model(const BarConfig& c, BasisKind basis = BasisKind::MPM) {
  // One cell more than the bar on the right: the pulled end moves into it.
  Model<1> m(Grid<1>(Vec<1>(0.0), Vec<1>(c.length / c.elements), {c.elements + 1}));
  m.materials = {std::make_shared<LinearElastic>(c.young_left, 0.0, 1.0),
                 std::make_shared<LinearElastic>(c.young_right, 0.0, 1.0)};
  const double a = c.split * c.length;
  if (basis == BasisKind::MPM) {  // points at the Gauss positions: the FEM quadrature
    add_gauss_points<1>(
        m.grid, {0}, {c.elements}, 2, [&](const Vec<1>& x) { return x[0] < a ? 0 : 1; }, m.points);
  } else {  // GIMP: domains must tile the bar, so the points sit at sub-cell centres
    add_regular_points<1>(
        m.grid, {0}, {c.elements}, 2, [&](const Vec<1>& x) { return x[0] < a; }, 0, 1.0, m.points);
    add_regular_points<1>(
        m.grid, {0}, {c.elements}, 2, [&](const Vec<1>& x) { return x[0] > a; }, 1, 1.0, m.points);
  }
  // The pull acts on every node at x >= L (a platen), so that material moving past x = L
  // stays loaded.
  m.constraints = {{0, 0, 0.0}, {c.elements, 0, c.end_displacement}, {c.elements + 1, 0, c.end_displacement}};
  m.basis = basis;
  return m;
}
}  // namespace

TEST(MpmBar, OneLoadStepIsTheFemSolution) {
  const BarConfig c = paper_bar(GradientVariant::None, 40);
  const BarResult fem = solve_bar(c);
  Model<1> m = bar_model(c);
  NewtonSettings s;
  s.load_steps = 1;
  run_quasi_static<1>(m, s);
  for (int p = 0; p < m.points.size(); ++p) {
    const double x0 = fem.points.position[p][0];
    const int e = static_cast<int>(x0 / (c.length / c.elements));
    const double xi = x0 / (c.length / c.elements) - e;
    const double u_fem = (1 - xi) * fem.u_classical[e] + xi * fem.u_classical[e + 1];
    EXPECT_NEAR(m.points.position[p][0] - x0, u_fem, 1e-15);
    EXPECT_NEAR(m.points.stress[p](0, 0), fem.point_stress_classical[p], 1e-11);
  }
}

// With many steps the points move (0.1 at the pulled end) and MPM artefacts appear, all
// measured here and documented in docs/mpm.md:
//  - standard MPM: a point crossing a cell boundary changes the quadrature of both cells
//    and the stress spikes (cell-crossing error), tens of percent here;
//  - cells holding points of both materials share one strain increment;
//  - material that moves past x = L into the platen cell stops straining and the last
//    cell is only partly filled.
// cpGIMP removes the crossing spikes. Tolerance asserted for cpGIMP with 10 and 100 steps:
// 2 % on the points away from the interface and end cells (measured 1.1 % and 1.3 %), at
// least ten times below standard MPM's (measured 85 % and 70 %).
TEST(MpmBar, ManyLoadStepsWithMovingPointsStayWithinTolerance) {
  const BarConfig c = paper_bar(GradientVariant::None, 40);
  const double sigma = closed_form(c).classical_stress(), h = c.length / c.elements;
  std::map<std::pair<BasisKind, int>, double> bulk_of;
  for (BasisKind basis : {BasisKind::MPM, BasisKind::CPGIMP})
    for (int steps : {10, 100}) {
      Model<1> m = bar_model(c, basis);
      NewtonSettings s;
      s.load_steps = steps;
      run_quasi_static<1>(m, s);
      double bulk = 0, all = 0;
      for (int p = 0; p < m.points.size(); ++p) {
        const double x = m.points.position[p][0], dev = std::abs(m.points.stress[p](0, 0) / sigma - 1.0);
        all = std::max(all, dev);
        if (std::abs(x - c.split * c.length) > 2 * h && x < c.length - h) bulk = std::max(bulk, dev);
      }
      std::cout << to_string(basis) << ", " << steps << " load steps: stress deviation from FEM, bulk points " << bulk
                << ", all points " << all << "\n";
      bulk_of[std::make_pair(basis, steps)] = bulk;
    }
  for (int steps : {10, 100}) {
    EXPECT_LT(bulk_of[std::make_pair(BasisKind::CPGIMP, steps)], 0.02) << steps << " steps";
    EXPECT_GT(bulk_of[std::make_pair(BasisKind::MPM, steps)], 10 * bulk_of[std::make_pair(BasisKind::CPGIMP, steps)])
        << steps << " steps";
  }
}
