// Requirement (fast guard of test_circular_footing; docs/axisymmetry.md): a rigid circular
// footing on weightless Tresca clay, axisymmetric with F-bar and the r-weighted ghost
// penalty, on the grid h = R/8 pushed to s/B = 0.025
// (examples/footing_circular_axisymmetric_2d.toml, and rough): the peak q / c lies above Eason &
// Shield's (1960) N_c (the node-row footing's collapse load converges from above) and
// within 7 % of it, smooth (5.69) and rough (6.05), and the rough footing carries more
// than the smooth one.
#include <gtest/gtest.h>

#include <iostream>
#include <string>

#include "CircularFooting.hpp"

using namespace gradmpm;
using namespace gradmpm::test;

TEST(CircularFooting, CoarseGridPeaksJustAboveEasonAndShield) {
  double peak[2] = {0.0, 0.0};
  for (const bool rough : {false, true}) {
    CaseFile cf = CaseFile::load(std::string(GRADMPM_SOURCE_DIR) + "/examples/footing_circular_axisymmetric_2d.toml",
                                 {rough ? R"(constraints[3].fix=["x","y"])" : "constraints[3].fix=[\"y\"]"});
    const FootingCurve c = run_circular_footing(cf, 0.05);
    const double nc = rough ? kRoughNc : kSmoothNc;
    for (std::size_t k = 0; k < c.q_over_c.size(); ++k)
      std::cout << (rough ? "rough" : "smooth") << " s/B " << c.s_over_b[k] << " q/c " << c.q_over_c[k] << "\n";
    peak[rough] = c.peak();
    std::cout << (rough ? "rough" : "smooth") << ", h = R/8: peak q/c " << peak[rough] << " against N_c " << nc
              << " (" << (peak[rough] / nc - 1.0) * 100.0 << " %)\n";
    EXPECT_GT(peak[rough], nc) << (rough ? "rough" : "smooth");
    EXPECT_LT(peak[rough], 1.07 * nc) << (rough ? "rough" : "smooth");
  }
  EXPECT_GT(peak[1], peak[0]) << "the rough footing carries more";
}
