#pragma once
// A rigid circular footing (radius R = 1) on weightless Tresca clay, axisymmetric (r-z), for
// the collapse load against Eason & Shield (1960): N_c = q / c = 5.69 smooth, 6.05 rough
// (Houlsby & Wroth 1983 agree to 1 %). The clay: a cylinder of radius 5 R and depth 5 R,
// Mohr-Coulomb with phi = psi = 0 (Tresca; von Mises is not Tresca in r-z), c = 10,
// E = 10000, nu = 0.3 (rigidity index G / c = 385), uGIMP with 2 x 2 points per cell,
// F-bar, ghost penalty alpha = 2e-3. The footing is the row of surface nodes r <= R,
// pushed down (smooth: free in r; rough: held in r); q = 2 pi |R_z| / (pi R^2), R_z
// being the row's reaction per radian. The grid holds one cell past the axis, the base
// and the far side, and three above the surface. examples/footing_circular_axisymmetric_2d.toml
// is this case on h = R/8, pushed by 0.05 in 10 steps.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "gradmpm/app/MpmCase.hpp"
#include "gradmpm/io/CaseFile.hpp"
#include "gradmpm/mpm/QuasiStatic.hpp"

namespace gradmpm::test {

constexpr double kSmoothNc = 5.69, kRoughNc = 6.05;  // Eason & Shield (1960)

/// The case: cell size h, the footing rough or smooth, pushed by `settlement` in `steps`.
inline std::string circular_footing(double h, bool rough, double settlement, int steps) {
  const double L = 5.0;
  const int n = static_cast<int>(std::lround(L / h));
  return fmt::format(R"([grid]
origin = [{0}, {0}]
cell_size = {1}
cells = [{2}, {3}]
[basis]
type = "gimp"
[materials.clay]
model = "mohr-coulomb"
young = 10000.0
poisson = 0.3
cohesion = 10.0
friction_angle = 0.0
dilation_angle = 0.0
[mpm]
axisymmetric = true
fbar = true
ghost_penalty = 2e-3
[[bodies]]
material = "clay"
min = [0.0, 0.0]
max = [5.0, 5.0]
points_per_cell = 2
[[constraints]]
min = [{0}, {0}]
max = [{4}, 0.0]
fix = ["x", "y"]
[[constraints]]
min = [{0}, {1}]
max = [0.0, {5}]
fix = ["x"]
[[constraints]]
min = [5.0, {1}]
max = [{4}, {5}]
fix = ["x"]
[[constraints]]
name = "footing"
min = [0.0, 5.0]
max = [1.0, 5.0]
fix = {6}
displacement = [0.0, {7}]
[load_steps]
count = {8}
[output]
vtk_every = 0
plot = false
)",
                     -h, h, n + 2, n + 4, L + h, L + 3 * h, rough ? R"(["x", "y"])" : R"(["y"])", -settlement,
                     steps);
}

struct FootingCurve {
  std::vector<double> s_over_b, q_over_c;
  double peak() const { return *std::max_element(q_over_c.begin(), q_over_c.end()); }
};

/// Runs the footing case `cf` (its constraints block "footing" pushed down by
/// `settlement`); q / c against s / B at every converged step.
inline FootingCurve run_circular_footing(CaseFile& cf, double settlement) {
  MpmCase<2> c = read_mpm_case<2>(cf);
  std::vector<int> footing;
  for (const auto& set : c.model.node_sets)
    if (set.name == "footing") footing = set.nodes;
  FootingCurve curve;
  run_quasi_static<2>(c.model, c.newton, [&](const Model<2>&, const StepInfo& info) {
    const Vector& R = info.grid_reaction();
    double rz = 0.0;
    for (int node : footing) rz += R[node * 2 + 1];
    curve.s_over_b.push_back(info.load_factor * settlement / 2.0);  // B = 2 R = 2
    curve.q_over_c.push_back(2.0 * std::abs(rz) / 10.0);            // 2 pi |R_z| / (pi R^2) / c
  });
  return curve;
}

inline FootingCurve run_circular_footing(double h, bool rough, double settlement, int steps) {
  CaseFile cf = CaseFile::parse(circular_footing(h, rough, settlement, steps), "circular_footing.toml");
  return run_circular_footing(cf, settlement);
}

}  // namespace gradmpm::test
