#include "gradmpm/app/MpmCase.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

#include "gradmpm/analytic/Column.hpp"
#include "gradmpm/app/CommonKeys.hpp"
#include "gradmpm/core/Errors.hpp"
#include "gradmpm/core/Timer.hpp"
#include "gradmpm/io/Csv.hpp"
#include "gradmpm/io/EmbeddedScripts.hpp"
#include "gradmpm/io/Python.hpp"
#include "gradmpm/io/StagedOutputs.hpp"
#include "gradmpm/io/Vtk.hpp"
#include "gradmpm/points/Generate.hpp"

namespace gradmpm {

namespace fs = std::filesystem;

int mpm_case_dimension(const CaseFile& cf) {
  const auto n = cf.integer_list("grid.cells");
  cf.require(n.size() >= 1 && n.size() <= 3, "grid.cells", "1 to 3 cell counts (one per dimension)");
  return static_cast<int>(n.size());
}

namespace {

constexpr const char* kAxes[3] = {"x", "y", "z"};

template <int dim>
Vec<dim> vec(const CaseFile& cf, const std::string& key) {
  const auto v = cf.numbers(key, dim);
  Vec<dim> out;
  for (int d = 0; d < dim; ++d) out[d] = v[d];
  return out;
}

bool inside_polygon(const std::vector<std::vector<double>>& poly, double x, double y) {
  bool in = false;  // even-odd rule
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const double xi = poly[i][0], yi = poly[i][1], xj = poly[j][0], yj = poly[j][1];
    if ((yi > y) != (yj > y) && x < (xj - xi) * (y - yi) / (yj - yi) + xi) in = !in;
  }
  return in;
}

template <int dim>
struct Box {
  Vec<dim> lo, hi;
  bool contains(const Vec<dim>& x, double tol) const {
    for (int d = 0; d < dim; ++d)
      if (x[d] < lo[d] - tol || x[d] > hi[d] + tol) return false;
    return true;
  }
};

template <int dim>
Box<dim> read_box(const CaseFile& cf, const std::string& prefix) {
  Box<dim> b{vec<dim>(cf, prefix + ".min"), vec<dim>(cf, prefix + ".max")};
  for (int d = 0; d < dim; ++d)
    cf.require(b.hi[d] >= b.lo[d], prefix + ".max", fmt::format("a corner with max >= min in every direction"));
  return b;
}

}  // namespace

template <int dim>
Model<dim> read_mpm_case(CaseFile& cf, NewtonSettings& newton, MpmOutputOptions& output, GradientSettings* gradient) {
  cf.declare_section("grid", {"origin", "cell_size", "cells"}, true);
  cf.declare_section("basis", {"type"}, false);
  cf.declare_table_of_sections("materials", {"model", "young", "poisson", "density"});
  cf.declare_array("bodies", {"material", "min", "max", "polygon", "points_per_cell"});
  cf.declare_section("loads", {"gravity"}, false);
  cf.declare_array("constraints", {"face", "min", "max", "fix", "displacement"});
  cf.declare_array("point_loads", {"min", "max", "force"});
  cf.declare_section("load_steps", {"count"}, true);
  cf.declare_section("nonlinear_solver", {"tolerance", "max_iterations", "max_cuts"}, false);
  declare_linear_solver_section(cf);
  cf.declare_section("output", {"vtk_every", "track", "check", "plot"}, false);
  cf.declare_section("gradient", {"variant", "length_scale", "apply", "fields"}, false);
  cf.reject_unknown();
  if (gradient) *gradient = read_gradient_settings(cf);

  // --- grid
  const auto cells = cf.integer_list("grid.cells");
  typename Grid<dim>::Index n;
  for (int d = 0; d < dim; ++d) {
    cf.require(cells[d] >= 1 && cells[d] <= 10'000'000, "grid.cells", "cell counts from 1 to 10000000");
    n[d] = static_cast<int>(cells[d]);
  }
  const Vec<dim> origin = vec<dim>(cf, "grid.origin");
  Vec<dim> h;  // one size for all directions, or one per direction
  if (cf.is_array("grid.cell_size"))
    h = vec<dim>(cf, "grid.cell_size");
  else
    h.setConstant(cf.number("grid.cell_size"));
  cf.require((h.array() > 0.0).all(), "grid.cell_size", "cell sizes > 0");
  Model<dim> m(Grid<dim>(origin, h, n));
  Vec<dim> grid_hi;
  for (int d = 0; d < dim; ++d) grid_hi[d] = origin[d] + n[d] * h[d];

  // --- basis
  const std::string basis = cf.string_or("basis.type", "mpm");
  const auto kind = parse_basis(basis);
  cf.require(kind.has_value(), "basis.type", "\"mpm\", \"gimp\" (uGIMP) or \"cpgimp\"");
  m.basis = *kind;

  // --- materials
  const auto names = cf.subsections("materials");
  if (names.empty()) throw InputError(fmt::format("{}: missing section [materials.NAME] (at least one material)", cf.name()));
  for (const auto& name : names) {
    const std::string k = "materials." + name;
    const std::string model = cf.string(k + ".model");
    cf.require(model == "hencky" || model == "linear-elastic", k + ".model", "\"hencky\" or \"linear-elastic\"");
    const double E = cf.number(k + ".young");
    cf.require(E > 0.0, k + ".young", "a Young's modulus > 0");
    const double nu = cf.number_or(k + ".poisson", 0.0);
    cf.require(nu > -1.0 && nu < 0.5, k + ".poisson", "a Poisson's ratio in (-1, 0.5)");
    const double rho = cf.number_or(k + ".density", 0.0);
    cf.require(rho >= 0.0, k + ".density", "a density >= 0");
    if (model == "hencky")
      m.materials.push_back(std::make_shared<Hencky>(E, nu, rho));
    else
      m.materials.push_back(std::make_shared<LinearElastic>(E, nu, rho));
  }

  // --- bodies: material points at sub-cell centres inside each body
  const std::size_t nb = cf.array_size("bodies");
  if (nb == 0) throw InputError(fmt::format("{}: missing [[bodies]] (at least one body of material points)", cf.name()));
  for (std::size_t b = 0; b < nb; ++b) {
    const std::string k = fmt::format("bodies[{}]", b);
    const std::string mat = cf.string(k + ".material");
    int mat_id = -1;
    for (std::size_t i = 0; i < names.size(); ++i)
      if (names[i] == mat) mat_id = static_cast<int>(i);
    cf.require(mat_id >= 0, k + ".material", fmt::format("the name of a [materials.NAME] section (one of: {})", fmt::join(names, ", ")));
    const long long ppc = cf.integer_or(k + ".points_per_cell", 2);
    cf.require(ppc >= 1 && ppc <= 8, k + ".points_per_cell", "an integer from 1 to 8 (points per cell and direction)");
    Box<dim> box;
    std::function<bool(const Vec<dim>&)> inside;
    if (cf.has(k + ".polygon")) {
      cf.require(dim == 2, k + ".polygon", "no polygon (polygons are for 2D cases; use min and max)");
      cf.require(!cf.has(k + ".min") && !cf.has(k + ".max"), k + ".polygon", "either a polygon or min/max, not both");
      const auto poly = cf.vector_list(k + ".polygon", 2);
      cf.require(poly.size() >= 3, k + ".polygon", "at least 3 vertices");
      box.lo.setConstant(std::numeric_limits<double>::max());
      box.hi.setConstant(std::numeric_limits<double>::lowest());
      for (const auto& v : poly)
        for (int d = 0; d < dim; ++d) {
          box.lo[d] = std::min(box.lo[d], v[d]);
          box.hi[d] = std::max(box.hi[d], v[d]);
        }
      inside = [poly](const Vec<dim>& x) { return inside_polygon(poly, x[0], x[dim > 1 ? 1 : 0]); };
    } else {
      box = read_box<dim>(cf, k);
      inside = [box](const Vec<dim>& x) { return box.contains(x, 0.0); };
    }
    for (int d = 0; d < dim; ++d)
      cf.require(box.lo[d] >= origin[d] - 1e-12 * h[d] && box.hi[d] <= grid_hi[d] + 1e-12 * h[d], k + (cf.has(k + ".polygon") ? ".polygon" : ".max"),
                 "a body inside the grid");
    typename Grid<dim>::Index first, last;
    for (int d = 0; d < dim; ++d) {
      first[d] = std::max(0, static_cast<int>(std::floor((box.lo[d] - origin[d]) / h[d])));
      last[d] = std::min(n[d], static_cast<int>(std::ceil((box.hi[d] - origin[d]) / h[d])));
    }
    const int added = add_regular_points<dim>(m.grid, first, last, static_cast<int>(ppc), inside, mat_id,
                                              m.materials[mat_id]->density, m.points);
    cf.require(added > 0, k + (cf.has(k + ".polygon") ? ".polygon" : ".max"), "a body holding at least one material point (it is smaller than a sub-cell)");
  }

  // --- loads
  if (cf.has("loads.gravity")) m.gravity = vec<dim>(cf, "loads.gravity");

  // --- constraints on grid nodes
  const double tol = 1e-9 * h.minCoeff();
  for (std::size_t c = 0; c < cf.array_size("constraints"); ++c) {
    const std::string k = fmt::format("constraints[{}]", c);
    Box<dim> sel;
    if (cf.has(k + ".face")) {
      const std::string face = cf.string(k + ".face");
      int axis = -1;
      for (int d = 0; d < dim; ++d)
        if (face.size() == 2 && face[0] == kAxes[d][0] && (face[1] == '-' || face[1] == '+')) axis = d;
      cf.require(axis >= 0, k + ".face", dim == 1 ? "\"x-\" or \"x+\"" : (dim == 2 ? "one of \"x-\", \"x+\", \"y-\", \"y+\"" : "one of \"x-\", \"x+\", \"y-\", \"y+\", \"z-\", \"z+\""));
      cf.require(!cf.has(k + ".min") && !cf.has(k + ".max"), k + ".face", "either a face or min/max, not both");
      sel.lo = origin;
      sel.hi = grid_hi;
      if (face[1] == '-') sel.hi[axis] = origin[axis];
      else sel.lo[axis] = grid_hi[axis];
    } else {
      sel = read_box<dim>(cf, k);
    }
    const auto fix = cf.string_list(k + ".fix");
    std::vector<int> comps;
    for (const auto& f : fix) {
      int axis = -1;
      for (int d = 0; d < dim; ++d)
        if (f == kAxes[d]) axis = d;
      cf.require(axis >= 0, k + ".fix", dim == 1 ? "[\"x\"]" : (dim == 2 ? "a list of \"x\", \"y\"" : "a list of \"x\", \"y\", \"z\""));
      comps.push_back(axis);
    }
    cf.require(!comps.empty(), k + ".fix", "at least one component to hold");
    Vec<dim> disp = Vec<dim>::Zero();
    if (cf.has(k + ".displacement")) disp = vec<dim>(cf, k + ".displacement");
    int selected = 0;
    for (int node = 0; node < m.grid.num_nodes(); ++node) {
      if (!sel.contains(m.grid.node_position(node), tol)) continue;
      ++selected;
      for (int comp : comps) m.constraints.push_back({node, comp, disp[comp]});
    }
    cf.require(selected > 0, k + (cf.has(k + ".face") ? ".face" : ".min"), "a node set holding at least one grid node");
  }

  // --- point loads
  for (std::size_t c = 0; c < cf.array_size("point_loads"); ++c) {
    const std::string k = fmt::format("point_loads[{}]", c);
    const Box<dim> sel = read_box<dim>(cf, k);
    const Vec<dim> f = vec<dim>(cf, k + ".force");
    int selected = 0;
    for (int p = 0; p < m.points.size(); ++p)
      if (sel.contains(m.points.position[p], tol)) {
        m.points.force[p] += f;
        ++selected;
      }
    cf.require(selected > 0, k + ".min", "a box holding at least one material point");
  }

  // --- load steps, Newton, output
  const long long steps = cf.integer("load_steps.count");
  cf.require(steps >= 1 && steps <= 1'000'000, "load_steps.count", "an integer from 1 to 1000000");
  newton.load_steps = static_cast<int>(steps);
  newton.tolerance = cf.number_or("nonlinear_solver.tolerance", 1e-9);
  cf.require(newton.tolerance > 0.0 && newton.tolerance < 1.0, "nonlinear_solver.tolerance", "a number in (0, 1)");
  const long long its = cf.integer_or("nonlinear_solver.max_iterations", 25);
  cf.require(its >= 1 && its <= 1000, "nonlinear_solver.max_iterations", "an integer from 1 to 1000");
  newton.max_iterations = static_cast<int>(its);
  const long long cuts = cf.integer_or("nonlinear_solver.max_cuts", 6);
  cf.require(cuts >= 0 && cuts <= 30, "nonlinear_solver.max_cuts", "an integer from 0 to 30");
  newton.max_cuts = static_cast<int>(cuts);
  newton.linear_solver = read_linear_solver_settings(cf);
  if (gradient) gradient->linear_solver = newton.linear_solver;

  const long long every = cf.integer_or("output.vtk_every", 1);
  cf.require(every >= 0, "output.vtk_every", "an integer >= 0 (0: no VTK output)");
  output.vtk_every = static_cast<int>(every);
  if (cf.has("output.track")) {
    output.track = cf.integer_list("output.track");
    for (long long id : output.track)
      cf.require(id >= 0 && id < m.points.size(), "output.track", fmt::format("point ids from 0 to {}", m.points.size() - 1));
  }
  output.check = cf.string_or("output.check", "");
  cf.require(output.check.empty() || output.check == "column", "output.check", "\"column\" (or no key)");
  output.plot = cf.boolean_or("output.plot", true);
  if (output.check == "column") {
    cf.require(m.materials.size() == 1 && m.materials[0]->name() == "hencky" && cf.number_or("materials." + names[0] + ".poisson", 0.0) == 0.0,
               "output.check", "\"column\" only for one Hencky material with poisson = 0");
    cf.require(nb == 1 && !cf.has("bodies[0].polygon"), "output.check", "\"column\" only for one box-shaped body");
    bool vertical = m.gravity[dim - 1] < 0.0;
    for (int d = 0; d + 1 < dim; ++d) vertical = vertical && m.gravity[d] == 0.0;
    cf.require(vertical, "output.check", "\"column\" only with gravity along -" + std::string(kAxes[dim - 1]));
  }
  return m;
}

namespace {

void write_now(const fs::path& dir, const std::string& name, const std::string& content) {
  StagedOutputs out(dir);
  out.write_text(name, content);
  out.commit();
}

template <int dim>
std::vector<double> xyz(const std::vector<Vec<dim>>& v) {
  std::vector<double> out;
  out.reserve(3 * v.size());
  for (const auto& x : v)
    for (int d = 0; d < 3; ++d) out.push_back(d < dim ? x[d] : 0.0);
  return out;
}

template <int dim>
std::string points_vtu(const Model<dim>& m, const EnrichedFields<dim>* g = nullptr) {
  const auto& P = m.points;
  VtkField disp{"displacement", 3, {}}, stress{"stress", 9, {}}, strain{"elastic_strain", 9, {}},
      volume{"volume", 1, P.volume}, mass{"mass", 1, P.mass}, material{"material", 1, {}, true}, id{"id", 1, {}, true};
  for (int p = 0; p < P.size(); ++p) {
    for (int d = 0; d < 3; ++d) disp.values.push_back(d < dim ? P.position[p][d] - P.original_position[p][d] : 0.0);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        stress.values.push_back(P.stress[p](i, j));
        strain.values.push_back(P.strain[p](i, j));
      }
    material.values.push_back(P.material[p]);
    id.values.push_back(p);
  }
  std::vector<VtkField> fields = {disp, stress, strain, volume, mass, material, id};
  if (g) {
    VtkField gd{"gradient_displacement", 3, {}}, gs{"gradient_stress", 9, {}}, ge{"gradient_strain", 9, {}};
    for (int p = 0; p < P.size(); ++p) {
      for (int d = 0; d < 3; ++d) gd.values.push_back(d < dim ? g->displacement[p][d] : 0.0);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          gs.values.push_back(g->stress[p](i, j));
          ge.values.push_back(g->strain[p](i, j));
        }
    }
    fields.push_back(gd);
    fields.push_back(ge);
    fields.push_back(gs);
  }
  return vtu_points(xyz<dim>(P.position), fields);
}

/// points_gradient.csv: the classical and the enriched fields of every point.
template <int dim>
std::string points_gradient_csv(const Model<dim>& m, const EnrichedFields<dim>& g) {
  const auto& P = m.points;
  std::vector<std::vector<double>> col(28);
  for (int p = 0; p < P.size(); ++p) {
    col[0].push_back(p);
    for (int d = 0; d < 3; ++d) {
      col[1 + d].push_back(d < dim ? P.position[p][d] : 0.0);
      col[4 + d].push_back(d < dim ? P.position[p][d] - P.original_position[p][d] : 0.0);
      col[7 + d].push_back(d < dim ? g.displacement[p][d] : 0.0);
    }
    static constexpr int sym[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {0, 2}};
    for (int c = 0; c < 6; ++c) {
      col[10 + c].push_back(P.strain[p](sym[c][0], sym[c][1]));
      col[16 + c].push_back(g.strain[p](sym[c][0], sym[c][1]));
      col[22 + c].push_back(g.stress[p](sym[c][0], sym[c][1]));
    }
  }
  static const char* names[28] = {"id",     "x",      "y",      "z",      "ux",     "uy",     "uz",
                                  "ux_g",   "uy_g",   "uz_g",   "exx",    "eyy",    "ezz",    "exy",
                                  "eyz",    "exz",    "exx_g",  "eyy_g",  "ezz_g",  "exy_g",  "eyz_g",
                                  "exz_g",  "sxx_g",  "syy_g",  "szz_g",  "sxy_g",  "syz_g",  "sxz_g"};
  CsvTable t;
  for (int c = 0; c < 28; ++c) t.add(names[c], col[c]);
  return t.str();
}

template <int dim>
std::string grid_vtu(const Model<dim>& m, const StepInfo* info) {
  const int nn = m.grid.num_nodes();
  VtkField du{"displacement_increment", 3, std::vector<double>(3 * nn, 0.0)}, mass{"mass", 1, std::vector<double>(nn, 0.0)};
  if (info) {
    for (int n = 0; n < nn; ++n) {
      for (int d = 0; d < dim; ++d) du.values[3 * n + d] = info->grid_displacement[n * dim + d];
      mass.values[n] = info->grid_mass[n];
    }
  }
  return vtu_grid<dim>(m.grid, {du, mass});
}

template <int dim>
std::string points_final_csv(const Model<dim>& m) {
  const auto& P = m.points;
  std::vector<std::vector<double>> col(15);
  for (int p = 0; p < P.size(); ++p) {
    col[0].push_back(p);
    for (int d = 0; d < 3; ++d) {
      col[1 + d].push_back(d < dim ? P.original_position[p][d] : 0.0);
      col[4 + d].push_back(d < dim ? P.position[p][d] : 0.0);
    }
    const auto& s = P.stress[p];
    const double comps[6] = {s(0, 0), s(1, 1), s(2, 2), s(0, 1), s(1, 2), s(0, 2)};
    for (int c = 0; c < 6; ++c) col[7 + c].push_back(comps[c]);
    col[13].push_back(P.volume[p]);
    col[14].push_back(P.mass[p]);
  }
  static const char* names[15] = {"id", "X", "Y", "Z", "x", "y", "z", "sxx", "syy", "szz", "sxy", "syz", "sxz", "volume", "mass"};
  CsvTable t;
  for (int c = 0; c < 15; ++c) t.add(names[c], col[c]);
  return t.str();
}

/// Compares the final state with the column closed form; writes column_check.csv and
/// (if asked) column.png; returns a one-line summary.
template <int dim>
std::string column_check(const Model<dim>& m, const fs::path& dir, bool plot) {
  const auto& P = m.points;
  double base = std::numeric_limits<double>::max(), top = std::numeric_limits<double>::lowest();
  for (int p = 0; p < P.size(); ++p) {
    base = std::min(base, P.original_position[p][dim - 1] - P.original_half_length[p][dim - 1]);
    top = std::max(top, P.original_position[p][dim - 1] + P.original_half_length[p][dim - 1]);
  }
  const auto* mat = m.materials[0].get();
  // Young's modulus from the tangent at rest (nu = 0: A_yyyy = E).
  MaterialResponse r;
  mat->update(Eigen::Matrix3d::Identity(), Eigen::Matrix3d::Zero(), r);
  Mat9 A;
  mat->tangent(r, dim, A);
  const analytic::Column col{top - base, mat->density, -m.gravity[dim - 1], A(3 * (dim - 1) + dim - 1, 3 * (dim - 1) + dim - 1)};
  std::vector<double> Y, s, se, y, ye;
  double err_s = 0, err_y = 0;
  for (int p = 0; p < P.size(); ++p) {
    Y.push_back(P.original_position[p][dim - 1] - base);
    s.push_back(P.stress[p](dim - 1, dim - 1));
    se.push_back(col.cauchy_stress(Y.back()));
    y.push_back(P.position[p][dim - 1] - base);
    ye.push_back(col.position(Y.back()));
    err_s = std::max(err_s, std::abs(s.back() - se.back()));
    err_y = std::max(err_y, std::abs(y.back() - ye.back()));
  }
  CsvTable t;
  t.add("Y", Y);
  t.add("stress", s);
  t.add("stress_exact", se);
  t.add("y", y);
  t.add("y_exact", ye);
  StagedOutputs out(dir);
  const auto csv = out.write_text("column_check.csv", t.str());
  if (plot) {
    const auto png = out.stage("column.png");
    run_python_script(embedded::plot_column_py,
                      {csv.string(), png.string(), fmt::format("{}D column, {} basis, {} points", dim, to_string(m.basis), P.size())});
  }
  out.commit();
  return fmt::format("column vs closed form: max |stress error| / (rho0 g H0) = {:.3e}, max |position error| / H0 = {:.3e}",
                     err_s / (col.density * col.gravity * col.height), err_y / col.height);
}

template <int dim>
void run(CaseFile& cf, const fs::path& dir, bool quiet) {
  NewtonSettings newton;
  MpmOutputOptions output;
  GradientSettings gradient;
  Model<dim> m = read_mpm_case<dim>(cf, newton, output, &gradient);
  StagedOutputs probe(dir);  // fails now, before solving, if the directory is unusable
  GradientStep<dim> gradient_step(m, gradient);
  double classical_seconds = 0.0;

  std::vector<std::pair<double, std::string>> pvd_points, pvd_grid;
  std::string history = "step,load_factor,iteration,residual\n";
  std::string tracked = "step,load_factor,id,x,y,z,sxx,syy,szz,sxy,syz,sxz\n";
  auto write_vtk = [&](int step, double lambda, const StepInfo* info) {
    const std::string pf = fmt::format("points_{:04d}.vtu", step), gf = fmt::format("grid_{:04d}.vtu", step);
    StagedOutputs out(dir);
    out.write_text(pf, points_vtu(m, gradient_step.fields()));
    out.write_text(gf, grid_vtu(m, info));
    pvd_points.emplace_back(lambda, pf);
    pvd_grid.emplace_back(lambda, gf);
    out.write_text("points.pvd", pvd(pvd_points));
    out.write_text("grid.pvd", pvd(pvd_grid));
    out.commit();
  };
  auto track = [&](int step, double lambda) {
    for (long long id : output.track) {
      double x[3] = {0.0, 0.0, 0.0};
      for (int d = 0; d < dim; ++d) x[d] = m.points.position[id][d];
      const auto& s = m.points.stress[id];
      fmt::format_to(std::back_inserter(tracked), "{},{},{},{},{},{},{},{},{},{},{},{}\n", step, lambda, id, x[0], x[1],
                     x[2], s(0, 0), s(1, 1), s(2, 2), s(0, 1), s(1, 2), s(0, 2));
    }
  };
  if (!quiet)
    fmt::print("gradmpm: {}D implicit MPM, {} points, {} grid nodes, basis {}, {} load step(s)\n", dim, m.points.size(),
               m.grid.num_nodes(), to_string(m.basis), newton.load_steps);
  if (output.vtk_every > 0) write_vtk(0, 0.0, nullptr);
  track(0, 0.0);

  const auto t0 = Clock::now();
  try {
    const RunSummary summary = run_quasi_static<dim>(m, newton, [&](const Model<dim>&, const StepInfo& info) {
      for (std::size_t k = 0; k < info.residuals.size(); ++k)
        fmt::format_to(std::back_inserter(history), "{},{},{},{}\n", info.step, info.load_factor, k, info.residuals[k]);
      track(info.step, info.load_factor);
      classical_seconds += info.seconds;
      const bool last = info.load_factor >= 1.0;
      const bool vtk_now = output.vtk_every > 0 && (info.step % output.vtk_every == 0 || last);
      gradient_step.after_step(m, vtk_now, last);  // docs/gradient-study.md
      if (vtk_now) write_vtk(info.step, info.load_factor, &info);
      StagedOutputs out(dir);
      out.write_text("newton_history.csv", history);
      if (!output.track.empty()) out.write_text("tracked_points.csv", tracked);
      out.commit();
      if (!quiet) {
        std::string res;
        for (double r : info.residuals) res += fmt::format(" {:.1e}", r);
        fmt::print("  step {:4d}  load {:.4f}  iterations {:2d}  cuts {}  residuals{}{}  ({:.2f} s)\n", info.step,
                   info.load_factor, static_cast<int>(info.residuals.size()) - 1, info.cuts, res,
                   info.indefinite_solves ? fmt::format("  [{} indefinite tangent(s), LU]", info.indefinite_solves) : "",
                   info.seconds);
        std::fflush(stdout);
      }
    });
    write_now(dir, "points_final.csv", points_final_csv(m));
    if (const auto* enriched = gradient_step.fields())
      write_now(dir, "points_gradient.csv", points_gradient_csv(m, *enriched));
    if (gradient_step.enabled() && !quiet)
      fmt::print("  gradient step ({}, l = {:g}, apply = {}, fields = {}): {:.3f} s = {:.1f} % of the classical solve\n",
                 to_string(gradient.variant), gradient.length_scale,
                 gradient.apply == GradientApply::End ? "end" : "each_step",
                 gradient.fields == GradientFields::Grid ? "grid" : "points", gradient_step.seconds(),
                 100.0 * gradient_step.seconds() / std::max(classical_seconds, 1e-12));
    if (!quiet)
      fmt::print("  done: {} steps, {} Newton iterations, {} cut(s), {:.2f} s\n", summary.steps, summary.total_iterations,
                 summary.cuts, seconds_since(t0));
    if (output.check == "column") {
      const std::string line = column_check(m, dir, output.plot);
      if (!quiet) fmt::print("  {}\n", line);
    }
    if (!quiet) fmt::print("  wrote {}/points_final.csv, newton_history.csv, points.pvd, grid.pvd\n", dir.string());
  } catch (const SolverError&) {
    if (!quiet) fmt::print("  stopped; the files of the converged steps in {} are complete\n", dir.string());
    throw;
  }
}

}  // namespace

void run_mpm_case(CaseFile& cf, const fs::path& out_dir, bool quiet) {
  switch (mpm_case_dimension(cf)) {
    case 1: return run<1>(cf, out_dir, quiet);
    case 2: return run<2>(cf, out_dir, quiet);
    default: return run<3>(cf, out_dir, quiet);
  }
}

template Model<1> read_mpm_case<1>(CaseFile&, NewtonSettings&, MpmOutputOptions&, GradientSettings*);
template Model<2> read_mpm_case<2>(CaseFile&, NewtonSettings&, MpmOutputOptions&, GradientSettings*);
template Model<3> read_mpm_case<3>(CaseFile&, NewtonSettings&, MpmOutputOptions&, GradientSettings*);

}  // namespace gradmpm
