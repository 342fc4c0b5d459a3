#pragma once
// Shared by the plasticity tests: the strip load on a block, and the measure of Newton's
// quadratic convergence.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace gradmpm::test {

/// [materials.clay] of the strip load: von Mises, E = 1000, nu = 0.3, sigma_y = 10, H = 50.
inline const std::string kVonMisesClay =
    "model = \"von-mises\"\nyoung = 1000.0\npoisson = 0.3\nyield_stress = 10.0\nhardening = 50.0\n";

/// A unit block on 8 x 8 cells (standard MPM basis): constraints[0] holds the base,
/// constraints[1] the left side (x), constraints[2] pushes the top nodes with
/// 0 <= x <= 0.25 down by 0.04 over 8 load steps. `clay`: the keys of [materials.clay].
inline std::string strip_load_case(const std::string& clay = kVonMisesClay) {
  return R"(
[grid]
origin = [0.0, 0.0]
cell_size = 0.125
cells = [8, 8]
[materials.clay]
)" + clay +
         R"(
[[bodies]]
material = "clay"
min = [0.0, 0.0]
max = [1.0, 1.0]
[[constraints]]
face = "y-"
fix = ["x", "y"]
[[constraints]]
min = [0.0, 0.0]
max = [0.0, 1.0]
fix = ["x"]
[[constraints]]
min = [0.0, 1.0]
max = [0.25, 1.0]
fix = ["y"]
displacement = [0.0, -0.04]
[load_steps]
count = 8
[output]
vtk_every = 0
)";
}

/// Newton's log r_k+1 / log r_k (2 for quadratic convergence) over the iterations with
/// r_k < 1e-3 whose next residual is above the round-off floor, 1e-12.
struct QuadraticRate {
  double worst = 10.0;
  int checked = 0;
  void add(const std::vector<double>& r) {
    for (std::size_t k = 1; k + 1 < r.size(); ++k)
      if (r[k] < 1e-3 && r[k + 1] > 1e-12) {
        worst = std::min(worst, std::log(r[k + 1]) / std::log(r[k]));
        ++checked;
      }
  }
};

}  // namespace gradmpm::test
