// Requirements of arc-length control ([arc_length]; NewtonSolver::solve_arc_length,
// docs/mpm.md "Arc-length control"):
//   A1 the classical softening bar (finite-strain von Mises with linear softening in one
//      weak cell, uniaxial strain) is traced through its snap-back: every converged step
//      lies on the 1D closed form of its load-displacement curve to 1e-6 (of the peak
//      force and of the peak displacement), and the grip's displacement falls after the
//      peak while the force falls to 2/3 of it (where the weak cell's yield stress reaches
//      0 and only its bulk stiffness is left: uniaxial strain);
//   A2 on an elastic bar arc-length gives the load-controlled answer (the closed form
//      F = E eps e^-eps of uniaxial strain) to round-off at every step, and stops at
//      max_load_factor;
//   A3 a case with arc-length and rigid boxes or [load_steps] is refused with the key named;
//   A5 the regularised bar (examples/softening_bar_1d.toml: implicit-gradient softening,
//      the staggered kappa_bar iteration inside each arc-length step) is traced past its
//      peak to a residual load, and its force at u = 1.01e-3 and 1.03e-3 is the
//      load-controlled run's to 0.1 %;
//   A4 displacement control of a load-driven case (an elastic bar pulled by a point load,
//      the free end's node controlled) moves that node by the same amount every step and
//      finds the load factor of the load-controlled answer, u(lambda) = lambda u(1), to 1e-9.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "gradmpm/app/MpmCase.hpp"
#include "gradmpm/core/Errors.hpp"
#include "gradmpm/materials/PlasticLaw.hpp"

using namespace gradmpm;

namespace {

// The bar x in [0, 1] on cells of h = 1/80, one point per cell; the cell 0.5 .. 0.5125
// weaker (sigma_y0 = 0.9); E = 1e7, nu = 0, H = -7.5e6 (the example's bar,
// examples/softening_bar_arclength_1d.toml, with E and H 1e4 times larger): strains of
// 1e-7. The MPM's incremental finite-strain quadrature (stencils and weights at the start
// of each step) departs from the continuum's closed form by the order of the strain (3e-4
// in force at the example's strains of 1e-3); here by less than 1e-6.
constexpr double kYoung = 1e7, kMu = 5e6, kH = -7.5e6, kWeakYield = 0.9, kWeak = 0.0125;

std::string bar_case(const std::string& control) {
  return R"(
[grid]
origin = [0.0]
cell_size = 0.0125
cells = [82]
[basis]
type = "mpm"
[materials.bar]
model = "von-mises"
young = 1.0e7
poisson = 0.0
density = 1.0
yield_stress = 1.0
hardening = -7.5e6
[materials.weak]
model = "von-mises"
young = 1.0e7
poisson = 0.0
density = 1.0
yield_stress = 0.9
hardening = -7.5e6
[[bodies]]
material = "bar"
min = [0.0]
max = [0.5]
points_per_cell = 1
[[bodies]]
material = "weak"
min = [0.5]
max = [0.5125]
points_per_cell = 1
[[bodies]]
material = "bar"
min = [0.5125]
max = [1.0]
points_per_cell = 1
[[constraints]]
min = [0.0]
max = [0.0]
fix = ["x"]
[[constraints]]
name = "end"
min = [1.0]
max = [1.025]
fix = ["x"]
displacement = [2.0e-7]
)" + control;
}

/// The strain eps of uniaxial strain whose Cauchy stress E eps e^-eps is sigma (the small root).
double elastic_strain_at(double sigma) {
  double eps = sigma / kYoung;
  for (int k = 0; k < 50; ++k) eps -= (kYoung * eps * std::exp(-eps) - sigma) / (kYoung * (1.0 - eps) * std::exp(-eps));
  return eps;
}

/// The closed form at the weak cell's plastic strain kappa > 0: its log strain from the
/// yield condition of uniaxial strain, 2 mu eps - 3 mu kappa = sigma_y0 + H kappa (the
/// exponential map is the small-strain return in log strains here), its Kirchhoff stress
/// 2 mu (eps - kappa), the Cauchy stress of the whole bar tau / J, J = e^eps, and the rest
/// of the bar elastic at that stress. Returns (grip displacement, force).
std::pair<double, double> softening_branch(double kappa) {
  const double eps_w = ((3.0 * kMu + kH) * kappa + kWeakYield) / (2.0 * kMu);
  const double sigma = 2.0 * kMu * (eps_w - kappa) * std::exp(-eps_w);
  const double eps_o = elastic_strain_at(sigma);
  return {(1.0 - kWeak) * std::expm1(eps_o) + kWeak * std::expm1(eps_w), sigma};
}

/// Force at the grip: the reactions of the grip's nodes.
double grip_force(const Model<1>& m, const StepInfo& info) {
  const Vector& r = info.grid_reaction();
  double f = 0.0;
  for (int n : m.node_sets.back().nodes) f += r[n];
  return f;
}

}  // namespace

TEST(ArcLength, A1TracesTheSnapBackOfTheSofteningBar) {
  CaseFile cf = CaseFile::parse(bar_case(R"(
[arc_length]
method = "relative-displacement"
from = [0.5]
to = [0.5125]
max_steps = 400
initial_increment = 0.05
max_load_factor = 0.5
)"),
                                "bar.toml");
  MpmCase<1> c = read_mpm_case<1>(cf);
  const double total = c.model.constraints.back().total;
  int weak = -1;
  for (int p = 0; p < c.model.points.size(); ++p)
    if (c.model.points.material[p] == 1) weak = p;
  double worst_u = 0.0, worst_f = 0.0, peak_f = 0.0, peak_u = 0.0, least_f = 1e300, u_at_peak = 0.0, least_u_after = 1e300;
  int on_branch = 0, steps = 0;
  run_quasi_static<1>(c.model, c.newton, [&](const Model<1>& m, const StepInfo& info) {
    ++steps;
    const double u = total * info.load_factor, f = grip_force(m, info);
    const double kappa = m.points.state_of(weak)[PlasticLaw::kKappa];
    if (kWeakYield + kH * kappa <= 0.0) return;  // past the softening: the bulk stiffness alone (not compared)
    if (f > peak_f) {
      peak_f = f;
      u_at_peak = u;
    }
    peak_u = std::max(peak_u, u);
    if (peak_f > 0.0 && f < peak_f) least_u_after = std::min(least_u_after, u);
    if (kappa > 0.0) {  // softening
      const auto [u_closed, f_closed] = softening_branch(kappa);
      worst_u = std::max(worst_u, std::abs(u - u_closed));
      worst_f = std::max(worst_f, std::abs(f - f_closed));
      least_f = std::min(least_f, f);
      ++on_branch;
    }
  });
  std::cout << "A1 " << steps << " steps, " << on_branch << " on the softening branch: peak force " << peak_f
            << " at u = " << u_at_peak << ", the grip back to u = " << least_u_after << ", force down to " << least_f
            << "; largest error against the closed form: u " << worst_u / peak_u << ", force " << worst_f / peak_f
            << " (of the peaks)\n";
  EXPECT_GE(on_branch, 8);
  EXPECT_LT(worst_u, 1e-6 * peak_u);
  EXPECT_LT(worst_f, 1e-6 * peak_f);
  EXPECT_LT(least_u_after, 0.7 * u_at_peak);  // snap-back: the grip moves back
  EXPECT_LT(least_f, 0.67 * peak_f);
}

TEST(ArcLength, A2ElasticBarFollowsTheLoadControlledAnswer) {
  std::string text = bar_case(R"(
[arc_length]
max_steps = 200
initial_increment = 0.1
max_load_factor = 0.4
)");
  // (both materials elastic here: yield far away)
  for (const char* from : {"yield_stress = 1.0", "yield_stress = 0.9"}) text.replace(text.find(from), std::strlen(from), "yield_stress = 100.0");
  CaseFile cf = CaseFile::parse(text, "bar.toml");
  MpmCase<1> c = read_mpm_case<1>(cf);
  const double total = c.model.constraints.back().total;
  double worst = 0.0, last = 0.0;
  int steps = 0;
  run_quasi_static<1>(c.model, c.newton, [&](const Model<1>& m, const StepInfo& info) {
    ++steps;
    const double u = total * info.load_factor, f = grip_force(m, info);
    worst = std::max(worst, std::abs(f - kYoung * std::log1p(u) / (1.0 + u)));
    last = info.load_factor;
  });
  std::cout << "A2 elastic bar: " << steps << " steps to load factor " << last
            << ", largest force error against E eps e^-eps: " << worst << "\n";
  EXPECT_LT(worst, 1e-6 * kYoung * total * 0.4);
  EXPECT_NEAR(last, 0.4, 1e-12);
}

TEST(ArcLength, A3RefusesWhatItCannotMove) {
  const auto refused = [](const std::string& extra, const std::string& key) {
    CaseFile cf = CaseFile::parse(bar_case("[arc_length]\nmax_steps = 5\n" + extra), "bar.toml");
    try {
      read_mpm_case<1>(cf);
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
      return;
    }
    ADD_FAILURE() << "accepted: " << extra;
  };
  refused("[load_steps]\ncount = 3\n", "arc_length");
  refused("[[rigid_boxes]]\nmin = [1.0]\nmax = [1.02]\ndisplacement = [-0.01]\n", "arc_length");
}

namespace {
std::string pulled_bar(const std::string& control) {
  return R"(
[grid]
origin = [0.0]
cell_size = 0.1
cells = [12]
[basis]
type = "mpm"
[materials.bar]
model = "linear-elastic"
young = 1.0e7
poisson = 0.0
density = 1.0
[[bodies]]
material = "bar"
min = [0.0]
max = [1.0]
points_per_cell = 2
[[point_loads]]
min = [0.95]
max = [1.0]
force = [1.0]
[[constraints]]
min = [0.0]
max = [0.0]
fix = ["x"]
[output]
track = [19]
)" + control;
}
}  // namespace

TEST(ArcLength, A4DisplacementControlOfALoadDrivenCase) {
  CaseFile load = CaseFile::parse(pulled_bar("[load_steps]\ncount = 1\n"), "bar.toml");
  MpmCase<1> once = read_mpm_case<1>(load);
  const int node = 10;  // x = 1
  double u_full = 0.0;
  run_quasi_static<1>(once.model, once.newton,
                      [&](const Model<1>&, const StepInfo& info) { u_full = info.grid_displacement()[node]; });
  CaseFile arc = CaseFile::parse(pulled_bar(R"(
[arc_length]
method = "displacement"
at = [1.0]
initial_increment = 0.1
max_steps = 7
max_load_factor = 100.0
)"),
                                 "bar.toml");
  MpmCase<1> c = read_mpm_case<1>(arc);
  double u = 0.0, worst = 0.0, first = 0.0;
  int steps = 0;
  run_quasi_static<1>(c.model, c.newton, [&](const Model<1>&, const StepInfo& info) {
    const double du = info.grid_displacement()[node];
    if (steps++ == 0) first = du;
    u += du;
    worst = std::max({worst, std::abs(du - first) / first, std::abs(u - info.load_factor * u_full) / u});
  });
  std::cout << "A4 displacement control: " << steps << " steps of du = " << first << " at x = 1, to load factor "
            << u / u_full << "; largest departure " << worst << "\n";
  EXPECT_EQ(steps, 7);
  EXPECT_LT(worst, 1e-9);
}

namespace {
/// The grip's (displacement, force) after every step of the regularised softening bar.
std::vector<std::pair<double, double>> regularised_bar(bool arc) {
  CaseFile cf = CaseFile::load(
      std::string(GRADMPM_SOURCE_DIR) + "/examples/softening_bar_1d.toml",
      arc ? std::vector<std::string>{"arc_length.method=\"relative-displacement\"", "arc_length.from=[0.3]",
                                     "arc_length.to=[0.7]", "arc_length.initial_increment=0.01",
                                     "arc_length.max_steps=400", "arc_length.max_load_factor=1.2",
                                     "output.vtk_every=0"}
          : std::vector<std::string>{"output.vtk_every=0"});
  if (arc) cf.remove_section("load_steps");
  MpmCase<1> c = read_mpm_case<1>(cf);
  const double total = c.model.constraints.back().total;
  std::vector<std::pair<double, double>> curve;
  run_quasi_static<1>(c.model, c.newton, [&](const Model<1>& m, const StepInfo& info) {
    curve.emplace_back(total * info.load_factor, grip_force(m, info));
  });
  return curve;
}

/// The force at displacement u, linear between the steps on either side (past the peak).
double force_at(const std::vector<std::pair<double, double>>& curve, double u) {
  std::size_t peak = 0;
  for (std::size_t k = 0; k < curve.size(); ++k)
    if (curve[k].second > curve[peak].second) peak = k;
  for (std::size_t k = peak + 1; k < curve.size(); ++k)
    if (curve[k].first >= u) {
      const auto [u0, f0] = curve[k - 1];
      const auto [u1, f1] = curve[k];
      return f0 + (u - u0) / (u1 - u0) * (f1 - f0);
    }
  return std::nan("");
}
}  // namespace

TEST(ArcLength, A5TracesTheRegularisedBarPastItsPeak) {
  const auto load = regularised_bar(false), arc = regularised_bar(true);
  double peak = 0.0, least = 1e300;
  for (const auto& [u, f] : arc) peak = std::max(peak, f);
  for (const auto& [u, f] : arc)
    if (u > 1.03e-3) least = std::min(least, f);
  std::cout << "A5 regularised bar, arc-length: " << arc.size() << " steps, peak force " << peak
            << ", down to " << least << " (u up to " << arc.back().first << ")";
  for (const double u : {1.01e-3, 1.03e-3})
    std::cout << "; at u = " << u << ": " << force_at(arc, u) << " (load control " << force_at(load, u) << ")";
  std::cout << "\n";
  for (const double u : {1.01e-3, 1.03e-3}) EXPECT_NEAR(force_at(arc, u) / force_at(load, u), 1.0, 1e-3) << u;
  EXPECT_LT(least, 0.85 * peak);
}
