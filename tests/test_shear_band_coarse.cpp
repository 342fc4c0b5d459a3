// Fast guards of the 2D shear-band requirements (test_shear_band_2d.cpp, label `long`),
// on the biaxial test with twice its length scale (l = 1/6, the weak patch l x l) on
// cells of h = l/2, to a platen displacement of 0.02:
//  C1 the regularised band is inclined at 45 +- 3 degrees to the loading axis (S2);
//  C2 the regularised band is at least 2 l thick, the classical band at most 2.5 h on the
//     same grid (S3: the thickness comes from l, not from the cells).
// S1 and S4 (the thickness independent of the grid, proportional to l) are guarded fast in
// 1D: Regularisation.BandWidthAndForceDoNotDependOnTheGrid, DoublingTheLengthScaleDoublesTheWidth.
// (A second grid here would be h = l/3 = 1/18, on which the example's supports hold no node.)
#include <gtest/gtest.h>

#include "BiaxialBand.hpp"

using namespace gradmpm;
using namespace gradmpm::test;

namespace {

constexpr double kCoarseL = 1.0 / 6.0;
constexpr double kCoarsePlaten = 0.02;  // past the peak (about 0.012 here) by as much as the example's 0.0125 is

TEST(ShearBandCoarse, RegularisedBandIsInclinedAt45DegreesAndThickerThanTheClassicalOne) {
  const BiaxialRun reg = run_biaxial(kL / kCoarseL, true, kCoarseL, kCoarsePlaten);  // h = l/2
  const BiaxialRun cls = run_biaxial(kL / kCoarseL, false, kCoarseL, kCoarsePlaten);
  ASSERT_FALSE(reg.failed) << reg.why;
  ASSERT_GE(reg.band.sections, 6);
  ASSERT_GE(cls.band.sections, 6) << cls.why;
  EXPECT_NEAR(reg.band.angle, 45.0, 3.0);                // C1
  EXPECT_GE(reg.band.thickness, 2.0 * kCoarseL);         // C2
  EXPECT_LE(cls.band.thickness, 2.5 * cls.h);            // C2
}

}  // namespace
