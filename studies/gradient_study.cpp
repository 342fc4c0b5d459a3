// gradient_study: answers the paper's two open questions on a multi-step large-deformation
// case, and measures the cost of the gradient step (docs/gradient-study.md).
//
//   build/studies/gradient_study OUT_DIR
//   /usr/bin/python3 scripts/plot_gradient_study.py OUT_DIR docs/figures
//
// Case: examples/column_bimaterial_1d.toml, a bi-material Hencky column under self-weight (1D; H0 = 10, lower half E =
// 80, upper half E = 400, rho0 g = 10, nu = 0; up to 48 % compression in the soft half), e-RA and u-RA with l = 1.
// Reference: a very fine grid (1024 cells) solved in ONE load step and smoothed once at the end. Compared: 20 load
// steps on 16 ... 128 cells with
//   apply = each_step, fields = points  (increments smoothed and carried by the points)
//   apply = end,       fields = grid    (the total field smoothed once, on the final points)
// (each_step + grid recomputes the total field at every report; its final answer is that
// of end + grid.) Writes study_errors.csv, study_profiles.csv and study_cost.csv.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <optional>

#include "gradmpm/app/MpmCase.hpp"

using namespace gradmpm;
namespace fs = std::filesystem;

namespace {

/// examples/column_bimaterial_1d.toml with `cells` cells over the height, `steps` load
/// steps and the given gradient choices.
CaseFile column(int cells, int steps, const std::string& variant, const std::string& apply, const std::string& fields) {
  const double h = 10.0 / cells;
  return CaseFile::load(fs::path(GRADMPM_SOURCE_DIR) / "examples" / "column_bimaterial_1d.toml",
                        {fmt::format("grid.origin=[{}]", -h), fmt::format("grid.cell_size={}", h),
                         fmt::format("grid.cells=[{}]", cells + 1), fmt::format("constraints[0].min=[{}]", -h),
                         fmt::format("load_steps.count={}", steps), "gradient.variant=" + variant,
                         "gradient.apply=" + apply, "gradient.fields=" + fields, "output.vtk_every=0"});
}

struct Run {
  std::vector<double> Y, eps_c, eps_g;  // sorted by Y
  double classical_s = 0, gradient_s = 0;
};

template <int dim>
Run solve(CaseFile cf) {
  MpmCase<dim> c = read_mpm_case<dim>(cf);
  Model<dim>& m = c.model;
  GradientStep<dim> gradient(m, c.gradient);
  Run r;
  run_quasi_static<dim>(m, c.newton, {&gradient},
                        [&](const Model<dim>&, const StepInfo& info) { r.classical_s += info.seconds; });
  r.gradient_s = gradient.seconds();
  const EnrichedFields<dim>& f = *gradient.fields();
  std::vector<int> order(m.points.size());
  for (int p = 0; p < m.points.size(); ++p) order[p] = p;
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return m.points.original_position[a][dim - 1] < m.points.original_position[b][dim - 1];
  });
  for (int p : order) {
    r.Y.push_back(m.points.original_position[p][dim - 1]);
    r.eps_c.push_back(m.elastic_strain(p)(dim - 1, dim - 1));
    r.eps_g.push_back(f.strain[p](dim - 1, dim - 1));
  }
  return r;
}

double interpolate(const Run& ref, double Y) {
  const auto it = std::lower_bound(ref.Y.begin(), ref.Y.end(), Y);
  if (it == ref.Y.begin()) return ref.eps_g.front();
  if (it == ref.Y.end()) return ref.eps_g.back();
  const std::size_t k = it - ref.Y.begin();
  const double t = (Y - ref.Y[k - 1]) / (ref.Y[k] - ref.Y[k - 1]);
  return (1 - t) * ref.eps_g[k - 1] + t * ref.eps_g[k];
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    fmt::print(stderr, "usage: gradient_study OUT_DIR\n");
    return 2;
  }
  const fs::path dir = argv[1];
  fs::create_directories(dir);
  std::ofstream errors(dir / "study_errors.csv"), profiles(dir / "study_profiles.csv"), cost(dir / "study_cost.csv");
  errors << "variant,choice,cells,max_error,l2_error\n";
  profiles << "variant,choice,cells,Y,eps_classical,eps_gradient\n";
  cost << "case,variant,choice,points,classical_s,gradient_s,ratio\n";

  for (const std::string variant : {"e-RA", "u-RA"}) {
    const Run ref = solve<1>(column(1024, 1, variant, "end", "grid"));
    for (std::size_t i = 0; i < ref.Y.size(); i += 8)
      profiles << fmt::format("{},reference,1024,{},{},{}\n", variant, ref.Y[i], ref.eps_c[i], ref.eps_g[i]);
    double scale = 0;
    for (double e : ref.eps_g) scale = std::max(scale, std::abs(e));
    fmt::print("{}: reference (1024 cells, 1 load step, smoothed at the end): peak |eps_g| = {:.5f}\n", variant, scale);
    for (const auto& [apply, fields] : {std::pair{"each_step", "points"}, std::pair{"end", "grid"}}) {
      const std::string choice = fmt::format("{}+{}", apply, fields);
      for (int cells : {16, 32, 64, 128}) {
        const Run r = solve<1>(column(cells, 20, variant, apply, fields));
        double emax = 0, el2 = 0;
        for (std::size_t i = 0; i < r.Y.size(); ++i) {
          const double d = r.eps_g[i] - interpolate(ref, r.Y[i]);
          emax = std::max(emax, std::abs(d));
          el2 += d * d;
        }
        el2 = std::sqrt(el2 / r.Y.size());
        errors << fmt::format("{},{},{},{},{}\n", variant, choice, cells, emax / scale, el2 / scale);
        fmt::print("  {:<16} cells {:4d}: max error {:.3e}, rms error {:.3e} (relative to the peak)\n", choice, cells,
                   emax / scale, el2 / scale);
        if (cells == 32)
          for (std::size_t i = 0; i < r.Y.size(); ++i)
            profiles << fmt::format("{},{},{},{},{},{}\n", variant, choice, cells, r.Y[i], r.eps_c[i], r.eps_g[i]);
        if (cells == 128)
          cost << fmt::format("column_1d,{},{},{},{},{},{}\n", variant, choice, r.Y.size(), r.classical_s, r.gradient_s,
                              r.gradient_s / r.classical_s);
      }
    }
  }

  // Cost in 2D: the footing example with e-RA, both choices.
  const fs::path src = fs::path(GRADMPM_SOURCE_DIR) / "examples" / "footing_2d.toml";
  for (const auto& [apply, fields] : {std::pair{"each_step", "points"}, std::pair{"end", "grid"}}) {
    CaseFile cf =
        CaseFile::load(src, {"gradient.variant=e-RA", "gradient.length_scale=0.25",
                             std::string("gradient.apply=") + apply, std::string("gradient.fields=") + fields});
    MpmCase<2> c = read_mpm_case<2>(cf);
    Model<2>& m = c.model;
    GradientStep<2> gradient(m, c.gradient);
    double cls = 0;
    run_quasi_static<2>(m, c.newton, {&gradient}, [&](const Model<2>&, const StepInfo& info) { cls += info.seconds; });
    const double grad = gradient.seconds();
    fmt::print("footing 2D, e-RA, {}+{}: classical {:.3f} s, gradient {:.3f} s, ratio {:.1f} %\n", apply, fields, cls,
               grad, 100 * grad / cls);
    cost << fmt::format("footing_2d,e-RA,{}+{},{},{},{},{}\n", apply, fields, m.points.size(), cls, grad, grad / cls);
  }
  fmt::print("wrote {}/study_errors.csv, study_profiles.csv, study_cost.csv\n", dir.string());
}
