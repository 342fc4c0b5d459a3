#include "gradmpm/app/BarMpm.hpp"

#include <cmath>
#include <optional>

#include "gradmpm/analytic/BimaterialBar.hpp"
#include "gradmpm/mpm/QuasiStatic.hpp"
#include "gradmpm/points/Generate.hpp"
#include "gradmpm/points/Transfer.hpp"

namespace gradmpm {

double bar_mpm_largest_compression(const BarMpmConfig& cfg) {
  const BarConfig& c = cfg.bar;
  const double h = c.length / c.elements;
  if (cfg.basis != BasisKind::MPM) return h;  // the last domain ends at the bar's end
  const int n = c.points_per_element;
  const double X = c.length - h * (1.0 - GaussRule01(n).xi[n - 1]);  // the last Gauss point
  const analytic::BimaterialBar unit{c.length, c.split * c.length, c.young_left, c.young_right, 1.0};
  return (X - (c.length - h)) / unit.classical_displacement(X);
}

BarResult solve_bar_mpm(const BarMpmConfig& cfg, double* gradient_seconds, double* classical_seconds) {
  const BarConfig& c = cfg.bar;
  const double h = c.length / c.elements, a = c.split * c.length;
  // Room for the pulled end: the grid reaches 2|delta| + 2h beyond x = L; every node there
  // is held at the end displacement (a platen).
  const int extra = static_cast<int>(std::ceil(2 * std::abs(c.end_displacement) / h)) + 2;
  Model<1> m(Grid<1>(Vec<1>(0.0), Vec<1>(h), {c.elements + extra}));
  m.basis = cfg.basis;
  m.materials = {std::make_shared<LinearElastic>(c.young_left, 0.0, 0.0),
                 std::make_shared<LinearElastic>(c.young_right, 0.0, 0.0)};
  if (cfg.basis == BasisKind::MPM) {
    add_gauss_points<1>(
        m.grid, {0}, {c.elements}, c.points_per_element, [&](const Vec<1>& x) { return x[0] < a ? 0 : 1; }, m.points);
  } else {  // GIMP domains must tile the bar
    add_regular_points<1>(
        m.grid, {0}, {c.elements}, c.points_per_element, [&](const Vec<1>& x) { return x[0] < a; }, 0, 0.0, m.points);
    add_regular_points<1>(
        m.grid, {0}, {c.elements}, c.points_per_element, [&](const Vec<1>& x) { return x[0] > a; }, 1, 0.0, m.points);
  }
  m.constraints = {{0, 0, 0.0}};
  for (int n = c.elements; n <= c.elements + extra; ++n) m.constraints.push_back({n, 0, c.end_displacement});

  GradientStep<1> gradient(m, cfg.gradient);
  NewtonSettings s;
  s.load_steps = cfg.load_steps;
  s.linear_solver = c.solver;
  double t_cls = 0;
  run_quasi_static<1>(m, s, {&gradient}, [&](const Model<1>&, const StepInfo& info) { t_cls += info.seconds; });
  // variant "none": the classical fields stand for the gradient ones
  const EnrichedFields<1> g = gradient.fields() ? *gradient.fields() : smooth_total<1>(m, cfg.gradient);
  if (gradient_seconds) *gradient_seconds = gradient.seconds();
  if (classical_seconds) *classical_seconds = t_cls;

  // Point fields, then nodal values by recovery on the nodes the material covers.
  BarResult r;
  r.points = m.points;
  const int np = m.points.size();
  std::vector<double> uc(np), ug(np);
  for (int p = 0; p < np; ++p) {
    r.point_young.push_back(m.material_of(p).elasticity().young);
    uc[p] = m.points.position[p][0] - m.points.original_position[p][0];
    ug[p] = g.displacement[p][0];
    r.point_strain_classical.push_back(m.elastic_strain(p)(0, 0));
    r.point_stress_classical.push_back(m.points.stress[p](0, 0));
    r.point_strain_gradient.push_back(g.strain[p](0, 0));
    r.point_stress_gradient.push_back(g.stress[p](0, 0));
  }
  const auto st = evaluate_stencils(m.grid, m.points, m.basis);
  const int nn = m.grid.num_nodes();
  const Vector nu_c = points_to_nodes(st, m.points, uc, nn), nu_g = points_to_nodes(st, m.points, ug, nn),
               ne_c = points_to_nodes(st, m.points, r.point_strain_classical, nn),
               ne_g = points_to_nodes(st, m.points, r.point_strain_gradient, nn),
               ns_c = points_to_nodes(st, m.points, r.point_stress_classical, nn),
               ns_g = points_to_nodes(st, m.points, r.point_stress_gradient, nn);
  const analytic::BimaterialBar bar{c.length, a, c.young_left, c.young_right, c.end_displacement};
  double end = 0;
  for (const auto& x : m.points.position) end = std::max(end, x[0]);
  std::vector<double> x, uc_n, ug_n, ec_n, eg_n, sc_n, sg_n;
  for (int n = 0; n < nn; ++n) {
    const double xn = m.grid.node_position(n)[0];
    if (xn > end) break;  // nodes beyond the material
    double X = xn;        // the material point now at the node: X = x - u(X)
    for (int it = 0; it < 100; ++it) X = xn - bar.classical_displacement(X);
    r.material_x.push_back(X);
    x.push_back(xn);
    uc_n.push_back(nu_c[n]);
    ug_n.push_back(nu_g[n]);
    ec_n.push_back(ne_c[n]);
    eg_n.push_back(ne_g[n]);
    sc_n.push_back(ns_c[n]);
    sg_n.push_back(ns_g[n]);
  }
  auto vec = [](const std::vector<double>& v) { return Vector(Eigen::Map<const Vector>(v.data(), v.size())); };
  r.x = x;
  r.u_classical = vec(uc_n);
  r.u_gradient = vec(ug_n);
  r.strain_classical = vec(ec_n);
  r.strain_gradient = vec(eg_n);
  r.stress_classical = vec(sc_n);
  r.stress_gradient = vec(sg_n);
  r.dofs = static_cast<int>(x.size());
  return r;
}

}  // namespace gradmpm
