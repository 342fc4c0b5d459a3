// Requirements on the factor of safety by strength reduction ([analysis] type =
// "strength-reduction", app/StrengthReduction.hpp):
//  - a reduced law is the law of the reduced parameters: Mohr-Coulomb with c / F and
//    tan(phi) / F (tan(psi) / F) yields on that law's surface, Drucker-Prager's cone is the
//    reduced angle's, von Mises' yield stress is sigma_y / F; a regularised law stays
//    regularised; elastic laws have no strength;
//  - on a layer sheared by a horizontal load (plane strain, the base fixed, the sides on
//    vertical rollers, the load on the top points of an elastic cap: uniform simple shear
//    tau in the layer; an elastic law keeps its stiffness), the factor found
//    brackets the closed form within the bisection's tolerance: von Mises, F = c_u / tau;
//    Mohr-Coulomb (sigma_n = 0 on the planes of largest shear), c cos(phi_F) / F = tau,
//    F = sqrt(c^2 / tau^2 - tan^2 phi);
//  - strength_reduction.csv has one row per trial, each trial's outputs are in its folder,
//    and a trial that fails keeps the files of its converged steps.
// (The refusals are lines of tests/bad_inputs/corpus.txt; Griffiths & Lane's slope is
// MpmCli.SlopeGmshFactorOfSafetyMeetsGriffithsAndLane in test_mpm_cli.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iostream>

#include "CliTestUtil.hpp"
#include "gradmpm/materials/DruckerPrager.hpp"
#include "gradmpm/materials/Hencky.hpp"
#include "gradmpm/materials/MohrCoulomb.hpp"
#include "gradmpm/materials/VonMises.hpp"

using namespace gradmpm;
using namespace gradmpm::test;

namespace {
const IsotropicElasticity kElastic(1e4, 0.3);
constexpr double kPi = 3.14159265358979323846;

double tan_deg(double d) { return std::tan(d * kPi / 180.0); }
double atan_deg(double t) { return std::atan(t) * 180.0 / kPi; }
}  // namespace

TEST(StrengthReduction, ReducedMohrCoulombYieldsOnTheReducedSurface) {
  const MohrCoulombParameters p{.cohesion = 10.0, .friction_angle = 30.0, .dilation_angle = 10.0};
  const MohrCoulomb law(kElastic, 2.0, p);
  const double F = 1.7;
  const auto reduced = std::dynamic_pointer_cast<const MohrCoulomb>(law.strength_reduced(F));
  ASSERT_NE(reduced, nullptr);
  const MohrCoulomb expected(kElastic, 2.0,
                             {.cohesion = 10.0 / F,
                              .friction_angle = atan_deg(tan_deg(30.0) / F),
                              .dilation_angle = atan_deg(tan_deg(10.0) / F)});
  // A stress on the reduced surface: k sigma_1 - sigma_3 = 2 c sqrt(k), sigma_3 = -100.
  const double phi = atan_deg(tan_deg(30.0) / F), s = std::sin(phi * kPi / 180.0), k = (1 + s) / (1 - s);
  const double s3 = -100.0, s1 = (s3 + 2.0 * (10.0 / F) * std::sqrt(k)) / k;
  const Eigen::Vector3d sorted(s1, 0.5 * (s1 + s3), s3);
  EXPECT_NEAR(reduced->yield(sorted), 0.0, 1e-12 * 100.0);
  EXPECT_NEAR(expected.yield(sorted), 0.0, 1e-12 * 100.0);
  EXPECT_LT(law.yield(sorted), -1.0);  // the unreduced law holds it with room to spare
  EXPECT_FALSE(reduced->symmetric_tangent());  // psi < phi stays so
  EXPECT_EQ(reduced->state_size(), law.state_size());
}

TEST(StrengthReduction, ReducedDruckerPragerAndVonMisesAreTheReducedParametersLaws) {
  const DruckerPrager dp(kElastic, 2.0, {.cohesion = 10.0, .friction_angle = 25.0, .dilation_angle = 25.0});
  const auto dp2 = std::dynamic_pointer_cast<const DruckerPrager>(dp.strength_reduced(1.5));
  ASSERT_NE(dp2, nullptr);
  const double phi = atan_deg(tan_deg(25.0) / 1.5);
  const DruckerPrager direct(kElastic, 2.0, {.cohesion = 10.0 / 1.5, .friction_angle = phi, .dilation_angle = phi});
  EXPECT_DOUBLE_EQ(dp2->eta(), direct.eta());
  EXPECT_DOUBLE_EQ(dp2->xi(), direct.xi());
  EXPECT_DOUBLE_EQ(dp2->cohesion(0.0), 10.0 / 1.5);
  EXPECT_TRUE(dp2->symmetric_tangent());

  const VonMises vm(kElastic, 2.0, {.yield_stress = 30.0, .hardening = -100.0, .residual_yield_stress = 6.0});
  const auto vm2 = std::dynamic_pointer_cast<const VonMises>(vm.strength_reduced(2.0));
  ASSERT_NE(vm2, nullptr);
  EXPECT_DOUBLE_EQ(vm2->yield_stress(0.0), 15.0);
  EXPECT_DOUBLE_EQ(vm2->yield_stress(1.0), 3.0);  // hardening and floor divided too
  // Regularised, then reduced: still regularised (its state holds kappa_bar).
  const auto regularised = std::dynamic_pointer_cast<const PlasticLaw>(vm.regularised(2.0));
  const auto both = std::dynamic_pointer_cast<const PlasticLaw>(regularised->strength_reduced(2.0));
  ASSERT_NE(both, nullptr);
  EXPECT_EQ(both->nonlocal_weight(), 2.0);
  EXPECT_EQ(both->state_size(), regularised->state_size());

  const Hencky elastic(1e4, 0.3, 2.0);
  EXPECT_FALSE(elastic.has_strength());
  EXPECT_EQ(elastic.strength_reduced(2.0), nullptr);
}

namespace {
/// A 2 x 2 layer (2 points per cell and direction) on a fixed base under a 2 x 1 elastic
/// cap, the sides on vertical rollers, the cap's top row of points pushed sideways by 4 x 3
/// = 12 over the width 2: tau = 6 in the layer (the cap's cell carries 9 in its lower
/// points: the load reaches the nodes below the top row too).
std::string sheared_layer(const std::string& material) {
  return R"([grid]
origin = [-1.0, -1.0]
cell_size = 1.0
cells = [4, 5]
[basis]
type = "gimp"
[materials.soil]
)" + material + R"(
[materials.cap]
model = "hencky"
young = 1.0e4
poisson = 0.3
density = 1.0
[[bodies]]
material = "soil"
min = [0.0, 0.0]
max = [2.0, 2.0]
[[bodies]]
material = "cap"
min = [0.0, 2.0]
max = [2.0, 3.0]
[[point_loads]]
min = [0.0, 2.5]
max = [2.0, 3.0]
force = [3.0, 0.0]
[[constraints]]
min = [-1.0, -1.0]
max = [3.0, 0.0]
fix = ["x", "y"]
[[constraints]]
min = [-1.0, -1.0]
max = [0.0, 4.0]
fix = ["y"]
[[constraints]]
min = [2.0, -1.0]
max = [3.0, 4.0]
fix = ["y"]
[load_steps]
count = 4
[analysis]
type = "strength-reduction"
failure_displacement = 1.0
[output]
vtk_every = 0
plot = false
)";
}

class ShearedLayer : public ScratchDirTest {
 protected:
  /// Runs the layer; returns the largest factor that stood and the smallest that failed.
  std::pair<double, double> factor_of_safety(const std::string& material) {
    const fs::path file = dir / "layer.toml";
    std::ofstream(file) << sheared_layer(material);
    const CliResult r = run_gradmpm("run " + file.string() + " --out " + (dir / "out").string());
    EXPECT_EQ(r.code, 0) << r.err;
    std::cout << r.out;
    const auto t = csv_columns(dir / "out" / "strength_reduction.csv");
    double stood = 0.0, failed = 1e9;
    for (std::size_t k = 0; k < t.at("factor").size(); ++k) {
      const double f = t.at("factor")[k];
      if (t.at("stands")[k] == 1.0) {
        stood = std::max(stood, f);
        EXPECT_EQ(t.at("load_factor")[k], 1.0);
      } else {
        failed = std::min(failed, f);
        EXPECT_LT(t.at("load_factor")[k], 1.0);
      }
    }
    return {stood, failed};
  }
};
}  // namespace

TEST_F(ShearedLayer, VonMisesFactorIsUndrainedStrengthOverShearStress) {
  const auto [stood, failed] =
      factor_of_safety("model = \"von-mises\"\nyoung = 1.0e4\npoisson = 0.3\ndensity = 1.0\nyield_stress = 17.320508075688775");
  const double exact = 10.0 / 6.0;  // c_u = sigma_y / sqrt(3) = 10
  std::cout << "von Mises: stands at " << stood << ", fails at " << failed << "; closed form " << exact << "\n";
  EXPECT_LE(failed - stood, 0.01 + 1e-12);
  EXPECT_LE(stood, exact * (1 + 1e-3));
  EXPECT_GE(failed, exact * (1 - 1e-3));
  // Every trial wrote its folder; a failed trial the files of its converged steps.
  EXPECT_TRUE(fs::exists(dir / "out" / "trials" / "01_F1.0000" / "points_final.csv"));
  EXPECT_TRUE(fs::exists(dir / "out" / "trials" / "02_F2.0000" / "newton_history.csv"));
  EXPECT_FALSE(fs::exists(dir / "out" / "trials" / "02_F2.0000" / "points_final.csv"));
}

TEST_F(ShearedLayer, MohrCoulombFactorMeetsTheClosedForm) {
  const auto [stood, failed] = factor_of_safety(
      "model = \"mohr-coulomb\"\nyoung = 1.0e4\npoisson = 0.3\ndensity = 1.0\ncohesion = 10.0\nfriction_angle = "
      "30.0\ndilation_angle = 0.0");
  const double exact = std::sqrt(100.0 / 36.0 - 1.0 / 3.0);  // c cos(phi_F) / F = tau
  std::cout << "Mohr-Coulomb: stands at " << stood << ", fails at " << failed << "; closed form " << exact << "\n";
  // (1e-3 of slack: Hencky's second-order normal stresses in simple shear, 0.01 beside
  // tau = 6, move the Mohr-Coulomb strength by 0.06 %.)
  EXPECT_LE(failed - stood, 0.01 + 1e-12);
  EXPECT_LE(stood, exact * (1 + 1e-3));
  EXPECT_GE(failed, exact * (1 - 1e-3));
}
