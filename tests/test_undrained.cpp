// Requirement: undrained loading by the coupled u-p MPM ([pore_pressure] drainage =
// "undrained", k = 0) of a smooth strip footing on von Mises clay (the effective stress's
// deviator is the total stress's, so the undrained strength is c): with F-bar its pressure
// follows the total-stress analysis of the same clay made nearly incompressible (nu =
// 0.499, F-bar) within 1 % from s/B = 0.01 to 0.025 (the plastic plateau; at first the
// u-p run is stiffer, its undrained nu -> 0.5), and reaches (2 + pi) c within 5 % at s/B =
// 0.025 (the total-stress run's own grid error at h = B/8 is 4.6 %, docs/plasticity.md).
// Neither locks: without F-bar the displacement-only run carries 6.2 c.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <numbers>

#include "CliTestUtil.hpp"

using namespace gradmpm::test;

namespace {

class Undrained : public ScratchDirTest {
 protected:
  /// (s / B, q / c) of the footing, 10 steps to s/B = 0.025.
  std::vector<std::pair<double, double>> footing(const std::string& extra, const std::string& name) {
    const std::string args = "run " + std::string(GRADMPM_SOURCE_DIR) +
                             "/examples/footing_tresca_2d.toml -q --set load_steps.count=10 "
                             "--set constraints[3].displacement=[0.0,-0.05] --set output.vtk_every=0 " +
                             extra + " --out " + (dir / name).string();
    const CliResult r = run_gradmpm(args);
    EXPECT_EQ(r.code, 0) << r.err;
    const auto t = csv_columns(dir / name / "reactions.csv");
    std::vector<std::pair<double, double>> curve;
    const auto& uy = t.at("uy");
    const auto& ry = t.at("ry");
    std::ifstream in(dir / name / "reactions.csv");
    std::string line;
    std::getline(in, line);
    for (std::size_t k = 0; std::getline(in, line); ++k)
      if (line.find(",footing,") != std::string::npos) curve.push_back({-uy[k] / 2.0, -ry[k] / 10.0});
    return curve;
  }
};

double at(const std::vector<std::pair<double, double>>& curve, double s) {
  for (std::size_t k = 1; k < curve.size(); ++k)
    if (curve[k].first >= s - 1e-12) {
      const auto [s0, q0] = curve[k - 1];
      const auto [s1, q1] = curve[k];
      return q0 + (q1 - q0) * (s - s0) / (s1 - s0);
    }
  return std::nan("");
}

}  // namespace

TEST_F(Undrained, AFootingOnUndrainedClayCarriesTheTotalStressAnalysissLoad) {
  const auto up = footing("--set materials.clay.porosity=0.4 --set pore_pressure.drainage=undrained", "up");
  const auto total = footing("--set materials.clay.poisson=0.499", "total");
  ASSERT_FALSE(up.empty());
  ASSERT_FALSE(total.empty());
  double worst = 0.0;
  std::cout << "  s/B      q/c u-p   q/c total stress\n";
  for (double s = 0.01; s <= 0.025 + 1e-12; s += 0.0025) {
    const double a = at(up, s), b = at(total, s);
    std::cout << "  " << s << "   " << a << "   " << b << "\n";
    worst = std::max(worst, std::abs(a - b) / b);
  }
  const double end = at(up, 0.025);
  std::cout << "  largest difference " << worst << "; q/c at s/B = 0.025: " << end << " (2 + pi = "
            << 2.0 + std::numbers::pi << ")\n";
  EXPECT_LT(worst, 0.01);
  EXPECT_NEAR(end, 2.0 + std::numbers::pi, 0.05 * (2.0 + std::numbers::pi));
}
