// Requirements on small strains: a step of tiny strain converges like a
// large one.
//  R1 linear elasticity at a prescribed displacement of 1e-3 ... 1e-9 on a 10 x 4 block
//     (strains 2.5e-4 ... 2.5e-10) converges in one Newton iteration without a cut, and the
//     stresses scale with the load to 1e-10 (the problem is linear): the strain is formed
//     from the increment's gradient, never from I + g - I;
//  R2 Hencky (finite strain) at tiny loads converges without a cut, its stresses per unit
//     load equal to linear elasticity's within the round-off of its logarithmic strain
//     (5e-15 / strain): below the round-off of the internal force Newton stops whatever the
//     relative residual says.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <iostream>

#include "gradmpm/app/MpmCase.hpp"

using namespace gradmpm;

namespace {
const char* kBlock = R"(
[grid]
origin = [0.0, 0.0]
cell_size = 1.0
cells = [10, 5]
[materials.a]
model = "linear-elastic"
young = 1000.0
poisson = 0.3
[[bodies]]
material = "a"
min = [0.0, 0.0]
max = [10.0, 4.0]
[[constraints]]
face = "y-"
fix = ["x", "y"]
[[constraints]]
min = [0.0, 4.0]
max = [4.0, 4.0]
fix = ["y"]
displacement = [0.0, -1.0]
[load_steps]
count = 1
[output]
vtk_every = 0
)";

struct Solved {
  std::vector<double> u;  ///< point stresses per unit prescribed displacement (positions carry the round-off of
                          ///< their size, not of the solve)
  int iterations = 0, cuts = 0;
};
Solved solve(const std::string& model, double delta) {
  CaseFile cf =
      CaseFile::parse(kBlock, "block.toml",
                      {"materials.a.model=" + model, fmt::format("constraints[1].displacement=[0.0,{}]", -delta)});
  MpmCase<2> c = read_mpm_case<2>(cf);
  Solved s;
  const RunSummary r = run_quasi_static<2>(c.model, c.newton);
  s.iterations = r.total_iterations;
  s.cuts = r.cuts;
  for (int p = 0; p < c.model.points.size(); ++p)
    for (int i = 0; i < 2; ++i)
      for (int j = i; j < 2; ++j) s.u.push_back(c.model.points.stress[p](i, j) / delta);
  return s;
}
double difference(const Solved& a, const Solved& b) {
  double num = 0.0, den = 0.0;
  for (std::size_t i = 0; i < a.u.size(); ++i) {
    num = std::max(num, std::abs(a.u[i] - b.u[i]));
    den = std::max(den, std::abs(b.u[i]));
  }
  return num / den;
}
}  // namespace

TEST(SmallStrain, LinearElasticityConvergesAtEveryLoadInOneIteration) {
  const Solved ref = solve("linear-elastic", 1e-3);
  for (double delta : {1e-5, 1e-7, 1e-9}) {
    Solved s;
    ASSERT_NO_THROW(s = solve("linear-elastic", delta)) << delta;
    const double diff = difference(s, ref);
    std::cout << "linear elasticity, delta = " << delta << ": " << s.iterations << " iteration(s), " << s.cuts
              << " cuts, stress / delta against delta = 1e-3: " << diff << "\n";
    EXPECT_EQ(s.iterations, 1) << delta;
    EXPECT_EQ(s.cuts, 0) << delta;
    EXPECT_LT(diff, 1e-10) << delta;
  }
}

TEST(SmallStrain, FiniteStrainConvergesAtTinyLoadsWithTheLinearAnswer) {
  const Solved linear = solve("linear-elastic", 1e-3);
  for (double delta : {1e-7, 1e-9}) {
    Solved s;
    ASSERT_NO_THROW(s = solve("hencky", delta)) << delta;
    const double diff = difference(s, linear);
    std::cout << "Hencky, delta = " << delta << ": " << s.iterations << " iteration(s), " << s.cuts
              << " cuts, stress / delta against linear elasticity: " << diff << "\n";
    EXPECT_EQ(s.cuts, 0) << delta;
    EXPECT_LE(s.iterations, 3) << delta;
    // Hencky's logarithmic strain carries the round-off of ln(1 + 2 eps), 1e-16 / eps relative.
    const double strain = delta / 4.0;
    EXPECT_LT(diff, 5e-15 / strain) << delta;
  }
}
