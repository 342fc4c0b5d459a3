// Requirements of the gradient study in 2D, on cases read from case-file text:
//  R1 bi-material plate in tension (nu = 0, E = [1000, 5000]): the e-RA smoothing zone
//     around the material interface has a width proportional to l, and once h << l it
//     does not depend on the grid spacing. Width w = integral |eps_g - eps_c| dA /
//     ((eps1 - eps2) * height), which is l for l << L in the 1D theory.
//  R2 plate with a sharp V-notch in tension: the classical peak strain grows without
//     bound under refinement (the notch-tip singularity), the e-RA peak converges.
//  R4 with linear_solver.type = "pcg" the classical solve and the gradient
//     step (u-RA with its Dirichlet nodes, e-RA, s-RA) use conjugate gradients and give the
//     direct solver's fields to 1e-8;
//  R3 (1D, large deformation) the paper's questions: on a bi-material Hencky column
//     (up to 48 % compression), e-RA applied once at the end to the total field (fields = grid)
//     converges to a fine single-step reference; increments smoothed after every step and
//     carried by the points (fields = points) converge to a different, path-dependent
//     answer (docs/gradient-study.md, studies/gradient_study.cpp).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>

#include "CaseTextUtil.hpp"
#include "gradmpm/app/MpmCase.hpp"

using namespace gradmpm;

namespace {
struct Result {
  Model<2> model;
  EnrichedFields<2> fields;
};

Result run_text(const std::string& text, const std::vector<std::string>& sets = {}) {
  CaseFile cf = CaseFile::parse(text, "study.toml", sets);
  MpmCase<2> c = read_mpm_case<2>(cf);
  run_quasi_static<2>(c.model, c.newton);
  EnrichedFields<2> f = smooth_total<2>(c.model, c.gradient);
  return {std::move(c.model), std::move(f)};
}

std::string plate(double h, double l) { return test::bimaterial_plate(h, l); }
}  // namespace

TEST(MpmGradient2D, BimaterialPlateSmoothingWidthScalesWithLengthScale) {
  for (double l : {0.05, 0.1}) {
    std::vector<double> widths;
    for (int per_l : {4, 8, 16}) {
      const double h = l / per_l;
      const Result r = run_text(plate(h, l));
      const auto& P = r.model.points;
      double e1 = 0, e2 = 0, w = 0;
      for (int p = 0; p < P.size(); ++p) (P.material[p] == 0 ? e1 : e2) = r.model.elastic_strain(p)(0, 0);
      for (int p = 0; p < P.size(); ++p)
        w += std::abs(r.fields.strain[p](0, 0) - r.model.elastic_strain(p)(0, 0)) * P.volume[p];
      w /= (e1 - e2) * 0.25;
      widths.push_back(w);
      std::cout << "l = " << l << "  h = l/" << per_l << "  width " << w << "  width / l " << w / l << "\n";
      EXPECT_NEAR(w / l, 1.0, 0.03) << "l = " << l << ", h = l/" << per_l;
    }
    EXPECT_NEAR(widths[2] / widths[1], 1.0, 0.01) << "grid independent once h << l";
  }
}

namespace {
std::string notch(double h) {
  const int n = static_cast<int>(std::lround(1.0 / h));
  return fmt::format(R"(
[grid]
origin = [{0}, {0}]
cell_size = {1}
cells = [{2}, {3}]
[materials.a]
model = "linear-elastic"
young = 1000.0
poisson = 0.3
[[bodies]]
material = "a"
polygon = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.0, 0.6], [0.5, 0.5], [0.0, 0.4]]
[[constraints]]
min = [{0}, {0}]
max = [2.0, 0.0]
fix = ["y"]
[[constraints]]
min = [1.0, {0}]
max = [2.0, 0.0]
fix = ["x"]
[[constraints]]
min = [{0}, 1.0]
max = [2.0, 2.0]
fix = ["y"]
displacement = [0.0, 0.001]
[load_steps]
count = 1
[gradient]
variant = "e-RA"
length_scale = 0.05
apply = "end"
)",
                     -h, h, n + 2, n + 2);
}
}  // namespace

TEST(MpmGradient2D, IterativeSolverGivesTheDirectSolversEnrichedFields) {
  for (const char* variant : {"u-RA", "e-RA", "s-RA"}) {
    const std::vector<std::string> sets = {fmt::format("gradient.variant=\"{}\"", variant)};
    std::vector<std::string> pcg = sets;
    pcg.push_back("linear_solver.type=\"pcg\"");
    const Result direct = run_text(plate(1.0 / 32, 0.1), sets), iterative = run_text(plate(1.0 / 32, 0.1), pcg);
    double scale = 0.0, diff = 0.0, udiff = 0.0;
    for (int p = 0; p < direct.model.points.size(); ++p) {
      scale = std::max(scale, direct.fields.strain[p].cwiseAbs().maxCoeff());
      diff = std::max(diff, (direct.fields.strain[p] - iterative.fields.strain[p]).cwiseAbs().maxCoeff());
      udiff = std::max(udiff, (direct.fields.displacement[p] - iterative.fields.displacement[p]).cwiseAbs().maxCoeff());
    }
    std::printf("%s: max strain difference pcg - cholmod %.2e (of %.2e), displacement %.2e\n", variant, diff, scale,
                udiff);
    EXPECT_LT(diff, 1e-8 * scale) << variant;
    EXPECT_LT(udiff, 1e-8 * 1e-3) << variant;
  }
}

TEST(MpmGradient2D, NotchPeakStrainDivergesClassicallyAndConvergesWithERA) {
  std::vector<double> classical, gradient;
  for (int n : {32, 64, 128}) {
    const Result r = run_text(notch(1.0 / n));
    double pc = 0, pg = 0;
    for (int p = 0; p < r.model.points.size(); ++p) {
      pc = std::max(pc, r.model.elastic_strain(p)(1, 1));
      pg = std::max(pg, r.fields.strain[p](1, 1));
    }
    classical.push_back(pc);
    gradient.push_back(pg);
    std::cout << "h = 1/" << n << "  peak eps_yy: classical " << pc << "  e-RA (l = 0.05) " << pg << "\n";
  }
  // Classical: the peak keeps growing by a roughly constant factor per halving of h.
  EXPECT_GT(classical[1] / classical[0], 1.15);
  EXPECT_GT(classical[2] / classical[1], 1.15);
  // e-RA: the change per halving shrinks and the last one is small.
  const double d1 = std::abs(gradient[1] - gradient[0]), d2 = std::abs(gradient[2] - gradient[1]);
  EXPECT_LT(d2, 0.6 * d1);
  EXPECT_LT(d2 / gradient[2], 0.05);
}

namespace {
/// examples/column_bimaterial_1d.toml (e-RA, l = 1) with `cells` cells and `steps` steps.
CaseFile bimaterial_column(int cells, int steps, const char* apply, const char* fields) {
  const double h = 10.0 / cells;
  return CaseFile::load(std::string(GRADMPM_SOURCE_DIR) + "/examples/column_bimaterial_1d.toml",
                        {fmt::format("grid.origin=[{}]", -h), fmt::format("grid.cell_size={}", h),
                         fmt::format("grid.cells=[{}]", cells + 1), fmt::format("constraints[0].min=[{}]", -h),
                         fmt::format("load_steps.count={}", steps), std::string("gradient.apply=") + apply,
                         std::string("gradient.fields=") + fields, "output.vtk_every=0"});
}

/// Final e-RA strain (vertical) against original height, sorted.
std::vector<std::pair<double, double>> column_profile(CaseFile cf) {
  MpmCase<1> c = read_mpm_case<1>(cf);
  Model<1>& m = c.model;
  GradientStep<1> gradient(m, c.gradient);
  run_quasi_static<1>(m, c.newton, {&gradient});
  const EnrichedFields<1>& f = *gradient.fields();
  std::vector<std::pair<double, double>> prof;
  for (int p = 0; p < m.points.size(); ++p) prof.emplace_back(m.points.original_position[p][0], f.strain[p](0, 0));
  std::sort(prof.begin(), prof.end());
  return prof;
}

double max_difference(const std::vector<std::pair<double, double>>& a,
                      const std::vector<std::pair<double, double>>& ref) {
  double d = 0;
  for (const auto& [Y, e] : a) {
    auto it = std::lower_bound(ref.begin(), ref.end(), std::make_pair(Y, -1e300));
    if (it == ref.begin()) ++it;
    if (it == ref.end()) --it;
    const auto& [Y1, e1] = *(it - 1);
    const auto& [Y2, e2] = *it;
    const double t = std::clamp((Y - Y1) / (Y2 - Y1), 0.0, 1.0);
    d = std::max(d, std::abs(e - ((1 - t) * e1 + t * e2)));
  }
  return d;
}
}  // namespace

TEST(MpmGradient2D, SmoothingTheFinalStateConvergesAndCarryingIncrementsDoesNot) {
  const auto ref = column_profile(bimaterial_column(256, 1, "end", "grid"));
  double peak = 0;
  for (const auto& [Y, e] : ref) peak = std::max(peak, std::abs(e));
  std::vector<double> end_err, step_err;
  for (int cells : {16, 64}) {
    end_err.push_back(max_difference(column_profile(bimaterial_column(cells, 20, "end", "grid")), ref) / peak);
    step_err.push_back(max_difference(column_profile(bimaterial_column(cells, 20, "each_step", "points")), ref) / peak);
    std::cout << "cells " << cells << ": max |eps_g - reference| / peak: end+grid " << end_err.back()
              << ", each_step+points " << step_err.back() << "\n";
  }
  EXPECT_LT(end_err[1], 0.25 * end_err[0]) << "end+grid converges to the reference";
  EXPECT_LT(end_err[1], 2e-3);
  EXPECT_GT(step_err[1], 0.03) << "carrying smoothed increments is path-dependent";
  EXPECT_NEAR(step_err[1], step_err[0], 0.2 * step_err[0]) << "and that difference does not shrink with h";
}
