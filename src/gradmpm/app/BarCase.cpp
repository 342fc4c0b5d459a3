#include "gradmpm/app/BarCase.hpp"
#include "gradmpm/app/MemoryCheck.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "gradmpm/analytic/BimaterialBar.hpp"
#include "gradmpm/app/CaseKeys.hpp"
#include "gradmpm/app/CommonKeys.hpp"
#include "gradmpm/io/Csv.hpp"
#include "gradmpm/io/EmbeddedScripts.hpp"
#include "gradmpm/io/Python.hpp"

namespace gradmpm {

BarConfig read_bar_config(CaseFile& cf, BarOutputOptions& output, BarMpmConfig* mpm) {
  const SectionSpec& bar = bar_section();
  cf.declare(bar);
  if (mpm) {
    cf.declare(bar_mpm_gradient_section());
    cf.declare(bar_mpm_section());
  } else {
    cf.declare(bar_gradient_section());
  }
  cf.declare(bar_output_section());
  declare_linear_solver_section(cf);
  cf.reject_unknown();

  BarConfig c;
  c.length = read_number(cf, "bar", bar.key("length"));
  c.elements = static_cast<int>(read_integer(cf, "bar", bar.key("elements")));
  c.split = read_number(cf, "bar", bar.key("split"));
  const auto young = cf.numbers("bar.young", 2);
  cf.require(young[0] > 0.0 && young[1] > 0.0, "bar.young", bar.key("young").expected());
  c.young_left = young[0];
  c.young_right = young[1];
  c.end_displacement = read_number(cf, "bar", bar.key("end_displacement"));
  c.points_per_element = static_cast<int>(read_integer(cf, "bar", bar.key("points_per_element")));
  require_memory(cf, "bar.elements", bar_memory_estimate(c.elements, c.points_per_element, mpm != nullptr),
                 fmt::format("{} elements, {} points each{}", c.elements, c.points_per_element, mpm ? ", as MPM" : ""),
                 true);

  const SectionSpec& gradient = bar_gradient_section();
  c.variant = *parse_gradient_variant(read_string(cf, "gradient", gradient.key("variant")));
  c.length_scale = c.variant == GradientVariant::None ? cf.number_or("gradient.length_scale", 0.0)
                                                      : read_number(cf, "gradient", gradient.key("length_scale"));
  cf.require(c.length_scale >= 0.0, "gradient.length_scale", gradient.key("length_scale").expected());
  c.solver = read_linear_solver_settings(cf);
  output.plot = read_boolean(cf, "output", bar_output_section().key("plot"));
  if (mpm) {
    mpm->bar = c;
    mpm->gradient = read_gradient_settings(cf);
    mpm->gradient.linear_solver = c.solver;
    const SectionSpec& m = bar_mpm_section();
    mpm->load_steps = static_cast<int>(read_integer(cf, "mpm", m.key("load_steps")));
    mpm->basis = *parse_basis(read_string(cf, "mpm", m.key("basis")));
    const double most = bar_mpm_largest_compression(*mpm);
    cf.require(c.end_displacement > -most, "bar.end_displacement",
               fmt::format("a compression less than {:.4g} (the bar's end held by the grid nodes at x >= L must "
                           "stay within their cells: one cell less the last point's distance from the end)",
                           most));
  }
  return c;
}

namespace {
analytic::BimaterialBar closed_form(const BarConfig& c) {
  return {c.length, c.split * c.length, c.young_left, c.young_right, c.end_displacement};
}
bool smooth_strain(GradientVariant v) { return v == GradientVariant::U_RA || v == GradientVariant::E_RA; }

/// Closed-form strain of the chosen variant at x; at the interface of a discontinuous
/// field the mean of the one-sided limits (what nodal recovery converges to).
double exact_strain(const BarConfig& c, double x, double interface_tol) {
  const auto bar = closed_form(c);
  if (smooth_strain(c.variant)) return bar.gradient_strain(x, c.length_scale);
  if (std::abs(x - bar.interface) <= interface_tol)
    return 0.5 * (bar.classical_stress() / c.young_left + bar.classical_stress() / c.young_right);
  return bar.classical_strain(x);
}
double exact_displacement(const BarConfig& c, double x) {
  const auto bar = closed_form(c);
  return smooth_strain(c.variant) ? bar.gradient_displacement(x, c.length_scale) : bar.classical_displacement(x);
}
}  // namespace

double bar_strain_error(const BarConfig& c, const BarResult& r) {
  const auto bar = closed_form(c);
  double err = 0.0, scale = 0.0;
  if (smooth_strain(c.variant)) {
    for (std::size_t i = 0; i < r.x.size(); ++i) {
      const double X = r.material_x.empty() ? r.x[i] : r.material_x[i];
      const double e = bar.gradient_strain(X, c.length_scale);
      err = std::max(err, std::abs(r.strain_gradient[i] - e));
      scale = std::max(scale, std::abs(e));
    }
  } else {
    for (int p = 0; p < r.points.size(); ++p) {
      const double e = bar.classical_strain(r.points.original_position[p][0]);
      err = std::max(err, std::abs(r.point_strain_gradient[p] - e));
      scale = std::max(scale, std::abs(e));
    }
  }
  return scale > 0.0 ? err / scale : err;
}

void write_bar_outputs(const BarConfig& c, const BarResult& r, StagedOutputs& out, const BarOutputOptions& options) {
  const double h = c.length / c.elements;
  std::vector<double> u_exact, strain_exact;
  for (std::size_t i = 0; i < r.x.size(); ++i) {
    const double X = r.material_x.empty() ? r.x[i] : r.material_x[i];
    u_exact.push_back(exact_displacement(c, X));
    strain_exact.push_back(exact_strain(c, X, 1e-9 * h));
  }
  CsvTable nodes;
  nodes.add("x", r.x);
  nodes.add("u_classical", r.u_classical);
  nodes.add("u_gradient", r.u_gradient);
  nodes.add("strain_classical", r.strain_classical);
  nodes.add("strain_gradient", r.strain_gradient);
  nodes.add("stress_classical", r.stress_classical);
  nodes.add("stress_gradient", r.stress_gradient);
  nodes.add("u_exact", u_exact);
  nodes.add("strain_exact", strain_exact);

  CsvTable points;
  std::vector<double> px, material;
  for (int p = 0; p < r.points.size(); ++p) {
    px.push_back(r.points.position[p][0]);
    material.push_back(r.points.material[p]);
  }
  points.add("x", px);
  points.add("volume", r.points.volume);
  points.add("material", material);
  points.add("young", r.point_young);
  points.add("strain_classical", r.point_strain_classical);
  points.add("strain_gradient", r.point_strain_gradient);
  points.add("stress_classical", r.point_stress_classical);
  points.add("stress_gradient", r.point_stress_gradient);

  const auto nodes_csv = out.write_text("bar.csv", nodes.str());
  const auto points_csv = out.write_text("bar_points.csv", points.str());
  if (options.plot) {
    const auto png = out.stage("bar.png");
    const std::string title = fmt::format("Bi-material bar, E = [{:g}, {:g}], {} with l = {:g}", c.young_left,
                                          c.young_right, to_string(c.variant), c.length_scale);
    run_python_script(embedded::plot_bar_py, {nodes_csv.string(), points_csv.string(), png.string(), title});
  }
  out.commit();
}

}  // namespace gradmpm
