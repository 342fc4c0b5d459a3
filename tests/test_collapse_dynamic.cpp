// Requirement (long tier): the vertical cut (examples/vertical_cut_dynamic_2d.toml) is
// followed dynamically through its collapse to rest: the run stops at rest before
// end_time (kinetic energy 1e-8 of its peak, inertia and damping forces 1e-4 of the forces
// in balance), the base then carries the block's weight to 1e-3, and the crest has
// slumped further than the quasi-static run's at full gravity (2.04 lower: the inertia
// carries the collapse on). Prints the run-out, the crest's motion and the time at rest
// (docs/dynamics.md). The fast tier guards the same: tests/test_dynamics.cpp D5 (a damped
// column comes to rest carrying its weight), test_mpm_cli (the cut's energy balance).
#include <gtest/gtest.h>

#include <iostream>

#include "gradmpm/app/MpmCase.hpp"

using namespace gradmpm;

TEST(CollapseDynamic, TheVerticalCutComesToRestCarryingItsWeight) {
  CaseFile cf = CaseFile::load(std::string(GRADMPM_SOURCE_DIR) + "/examples/vertical_cut_dynamic_2d.toml",
                               {"output.vtk_every=0"});
  MpmCase<2> c = read_mpm_case<2>(cf);
  Model<2>& m = c.model;
  double weight = 0.0;
  for (int p = 0; p < m.points.size(); ++p) weight += 9.81 * m.points.mass[p];
  const int crest = 4095;
  const Vec<2> crest0 = m.points.position[crest];
  StepInfo last;
  double base = 0.0, peak = 0.0;
  run_quasi_static<2>(m, c.newton, [&](const Model<2>& mm, const StepInfo& info) {
    last.time = info.time;
    last.step = info.step;
    last.at_rest = info.at_rest;
    last.kinetic_energy = info.kinetic_energy;
    peak = std::max(peak, info.kinetic_energy);
    if (!info.last) return;
    const Vector& r = info.grid_reaction();
    base = 0.0;
    for (int n : mm.node_sets.front().nodes) base += r[2 * n + 1];
  });
  double toe = 0.0;
  for (int p = 0; p < m.points.size(); ++p) toe = std::max(toe, m.points.position[p][0]);
  const Vec<2> moved = m.points.position[crest] - crest0;
  std::cout << "vertical cut, dynamic: at rest at t = " << last.time << " s (step " << last.step
            << ", kinetic energy " << last.kinetic_energy / peak << " of its peak); base reaction " << base
            << " against the weight " << weight << "; crest " << -moved[1] << " lower, " << moved[0]
            << " further out (quasi-static at full gravity: 2.04, 1.49); toe at x = " << toe << " (face at 8)\n";
  EXPECT_TRUE(last.at_rest);
  EXPECT_LT(last.time, 30.0);
  EXPECT_NEAR(base / weight, 1.0, 1e-3);
  EXPECT_GT(-moved[1], 2.04);
}
