// Requirement: gradmpm gives AMPLE's answer on AMPLE's own elasto-plastic case
// (AMPLE-m 1.1, setup/setupGrid_collapse.m; examples/collapse_ample_2d.toml): a von Mises
// block collapsing under gravity, standard MPM basis, 3 x 3 points per cell, 40 load
// steps, Newton to 1e-9. Every step converges (AMPLE's do; with an exact `f > 0` yield
// test the run stopped at step 35, 34 or 39 by the linear solver's round-off), and the
// crest point settles AMPLE's 1.7554381896 (Octave) at full gravity to 1e-8.
#include <gtest/gtest.h>

#include <iomanip>
#include <iostream>

#include "CliTestUtil.hpp"

using namespace gradmpm::test;

using AmpleCollapse = ScratchDirTest;

TEST_F(AmpleCollapse, EveryStepConvergesAndTheCrestSettlesAsInAmple) {
  const std::string example = std::string(GRADMPM_SOURCE_DIR) + "/examples/collapse_ample_2d.toml";
  for (const std::string solver : {"cholmod", "umfpack"}) {
    const fs::path out = dir / solver;
    const CliResult r = run_gradmpm("run " + example + " -q --set output.vtk_every=0 --set output.plot=false" +
                                    " --set linear_solver.type=" + solver + " --out " + out.string());
    ASSERT_EQ(r.code, 0) << solver << "\n" << r.err;
    const auto history = csv_columns(out / "newton_history.csv");
    EXPECT_EQ(history.at("step").back(), 40.0) << solver << ": 40 steps";
    EXPECT_EQ(history.at("load_factor").back(), 1.0) << solver;
    const auto crest = csv_columns(out / "tracked_points.csv");
    ASSERT_EQ(crest.at("id").back(), 575.0);
    ASSERT_NEAR(crest.at("y").front(), 7.0 + 5.0 / 6.0, 1e-12) << "the crest point starts at y = 7.833";
    const double settlement = crest.at("y").front() - crest.at("y").back();
    std::cout << solver << ": crest settlement at full gravity " << std::setprecision(11) << settlement
              << " (AMPLE 1.7554381896)\n";
    EXPECT_NEAR(settlement, 1.7554381896, 1e-8) << solver;
  }
}
