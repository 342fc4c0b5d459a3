#pragma once
// Geostatic initial stresses ([initial_stress]; docs/pore-pressure.md, "Initial stresses"):
// the K0 procedure of geotechnical finite-element codes (PLAXIS's, Anura3D's) on the points.
// Each point starts at rest under the weight of what lies above it:
//   sigma_v = |g| (sum of the masses above it in its column of grid cells + half its own
//             row's) / the column's cross-section,
// which is rho g d for a point d below the surface of a uniform body, and follows layers
// and a sloping surface column by column. Below the water table ([pore_pressure]
// water_table) the pore pressure is hydrostatic, p = rho_w |g| (z_w - z), and the
// effective stresses are
//   sigma'_v = sigma_v - p,  sigma'_h = K0 sigma'_v (every horizontal direction, the
//   out-of-plane one included), no shear.
// Each law writes the state that carries sigma' (Material::start_from_stress), and gravity
// becomes a dead load (Model::dead_gravity): it acts in full from the first step, so the
// body starts in balance and the load steps add only the other loads.
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "gradmpm/mpm/Model.hpp"

namespace gradmpm {

struct InitialStressSettings {
  double k0 = 1.0;  ///< sigma'_h / sigma'_v
};

/// The axis gravity acts along, or -1 unless it acts along exactly one grid axis.
template <int dim>
int vertical_axis(const Vec<dim>& gravity) {
  int axis = -1;
  for (int d = 0; d < dim; ++d)
    if (gravity[d] != 0.0) axis = axis < 0 ? d : dim;
  return axis < dim ? axis : -1;
}

/// The hydrostatic pore pressure at point p's current place: rho_w |g| times its depth below
/// the water table (PoreSettings::water_table, which needs gravity along one axis), 0
/// above it or without a water table.
template <int dim>
double hydrostatic_pressure(const Model<dim>& m, int p) {
  const int v = vertical_axis<dim>(m.gravity);
  if (!m.pore.water_table || v < 0) return 0.0;
  const double up = m.gravity[v] < 0.0 ? 1.0 : -1.0;
  const double depth = std::max(0.0, up * (*m.pore.water_table - m.points.position[p][v]));
  return m.pore.fluids[m.points.material[p]].density * std::abs(m.gravity[v]) * depth;
}

/// The total vertical stress (compression positive) at every point: the weight above it in
/// its column of grid cells per unit cross-section; points at one elevation carry half of
/// their row's weight. Axisymmetric (r-z, gravity along z): the masses are per radian, and
/// so is the column's cross-section, the integral of r dr over its cells' r > 0.
template <int dim>
std::vector<double> overburden(const Model<dim>& m, int v) {
  const auto& pts = m.points;
  const Vec<dim> h = m.grid.cell_size();
  const double g = std::abs(m.gravity[v]), up = m.gravity[v] < 0.0 ? 1.0 : -1.0;
  double area = 1.0;
  for (int d = 0; d < dim; ++d)
    if (d != v) area *= h[d];
  // The points of each column of cells: its number counts the cells across (v skipped).
  const auto cells = m.grid.cells();
  int count = 1;
  for (int d = 0; d < dim; ++d)
    if (d != v) count *= cells[d];
  std::vector<std::vector<int>> columns(count);
  for (int p = 0; p < pts.size(); ++p) {
    int column = 0;
    for (int d = dim - 1; d >= 0; --d)
      if (d != v) {
        const int i = static_cast<int>(std::floor((pts.position[p][d] - m.grid.origin()[d]) / h[d]));
        column = column * cells[d] + std::clamp(i, 0, cells[d] - 1);
      }
    columns[column].push_back(p);
  }
  std::vector<double> sigma(pts.size(), 0.0);
  const double tol = 1e-9 * h[v];
  for (std::size_t c = 0; c < columns.size(); ++c) {
    auto& members = columns[c];
    if (m.axisymmetric) {  // (v = 1: the column's cells span r0 .. r0 + h_r)
      const double r0 = std::max(m.grid.origin()[0] + static_cast<double>(c) * h[0], 0.0);
      const double r1 = std::max(m.grid.origin()[0] + static_cast<double>(c + 1) * h[0], 0.0);
      area = 0.5 * (r1 * r1 - r0 * r0);
    }
    std::sort(members.begin(), members.end(),
              [&](int a, int b) { return up * pts.position[a][v] > up * pts.position[b][v]; });
    double above = 0.0;
    for (std::size_t i = 0; i < members.size();) {  // one row (one elevation) at a time
      std::size_t j = i;
      double row = 0.0;
      while (j < members.size() && std::abs(pts.position[members[j]][v] - pts.position[members[i]][v]) <= tol)
        row += pts.mass[members[j++]];
      for (std::size_t k = i; k < j; ++k) sigma[members[k]] = g * (above + 0.5 * row) / area;
      above += row;
      i = j;
    }
  }
  return sigma;
}

/// What start_geostatic found wrong: the case's key to blame and what it needed;
/// empty when all is well.
struct GeostaticProblem {
  std::string key, expected;
  bool empty() const { return expected.empty(); }
};

/// Starts every point from the geostatic stress: its state, stress and pore pressure, and
/// makes gravity a dead load. Returns what is wrong: a law that cannot start from a stress,
/// an effective stress in tension, or a stress outside a law's yield surface, naming the
/// first point where it happens.
template <int dim>
GeostaticProblem start_geostatic(Model<dim>& m, const InitialStressSettings& s) {
  const int v = vertical_axis<dim>(m.gravity);
  if (v < 0) return {"loads.gravity", "gravity along one grid axis ([initial_stress] needs it)"};
  if (m.axisymmetric && v != 1)
    return {"loads.gravity", "gravity along the axis (y) in an axisymmetric case ([initial_stress] needs it)"};
  const std::vector<double> sigma_v = overburden(m, v);
  auto& pts = m.points;
  if (!m.state_initialised()) m.initialise_state();
  MaterialResponse response;
  std::vector<double> trial(static_cast<std::size_t>(pts.state_stride));
  for (int p = 0; p < pts.size(); ++p) {
    const Material& mat = m.material_of(p);
    const auto where = [&] {  // (only for a message)
      std::string at;
      for (int d = 0; d < dim; ++d) at += fmt::format("{}{:.6g}", d ? ", " : "", pts.position[p][d]);
      return fmt::format("at the point ({}) of material model \"{}\"", at, mat.model());
    };
    const double pore = m.pore.active() ? hydrostatic_pressure(m, p) : 0.0;
    const double effective = sigma_v[p] - pore;
    if (!(effective > 0.0))
      return {m.pore.water_table ? "pore_pressure.water_table" : "initial_stress.k0",
              fmt::format("an effective vertical stress > 0 {} (it is {:.6g}: a water table above the ground, or "
                          "nothing heavy above it?)",
                          where(), effective)};
    Mat3 stress = Mat3::Zero();
    for (int d = 0; d < 3; ++d) stress(d, d) = -(d == v ? 1.0 : s.k0) * effective;
    double* state = pts.state_of(p);
    if (!mat.start_from_stress(stress, state)) return {"initial_stress.k0", "laws that can start from a stress (not " + where() + ")"};
    // At rest (dF = I) the law must give the stress back: inside or on its yield surface.
    mat.update(Mat3::Identity(), state, trial.data(), response);
    if (!((response.stress - stress).norm() <= 1e-8 * stress.norm()))
      return {"initial_stress.k0", fmt::format("a K0 stress inside the yield surface {} (sigma'_v = {:.6g})", where(), effective)};
    pts.stress[p] = stress;
    pts.pore_pressure[p] = pore;
    pts.work[p] = m.elastic_energy(p);  // (the stored energy it starts with: nothing dissipated yet)
  }
  m.dead_gravity = true;
  return {};
}

}  // namespace gradmpm
