#pragma once
// Shared model builders of the MPM tests.
#include <Eigen/Dense>
#include <memory>
#include <random>

#include <string>

#include "gradmpm/analytic/Column.hpp"
#include "gradmpm/app/MpmCase.hpp"
#include "gradmpm/core/Errors.hpp"
#include "gradmpm/materials/Hencky.hpp"
#include "gradmpm/materials/LinearElastic.hpp"
#include "gradmpm/mpm/LoadStep.hpp"
#include "gradmpm/mpm/QuasiStatic.hpp"
#include "gradmpm/points/Generate.hpp"

namespace gradmpm::test {

/// The message of the InputError that reading `cf` as an MPM case throws; "" when it reads.
template <int dim>
std::string read_error(CaseFile cf) {
  try {
    read_mpm_case<dim>(cf);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

/// The large-deformation column: H0 = 10, rho0 = 1, g = 10, E = 80 (rho0 g H0 / E = 1.25,
/// final height 0.691 H0), Hencky, nu = 0, 2 points per cell and direction.
/// 1D: the axis is the height. 2D: one cell wide, rollers on both sides.
inline constexpr double kH0 = 10.0, kRho = 1.0, kG = 10.0, kE = 80.0;

inline analytic::Column column_closed_form() { return {kH0, kRho, kG, kE}; }

template <int dim>
Model<dim> make_column(int cells, BasisKind basis, int ppc = 2) {
  // One extra cell below the base, so that GIMP domains of the lowest points may extend
  // below y = 0 where every node is fixed (the support is not the grid boundary).
  const double h = kH0 / cells;
  Vec<dim> origin = Vec<dim>::Zero(), size = Vec<dim>::Constant(h);
  origin[dim - 1] = -h;
  typename Grid<dim>::Index n, first{}, last;
  n.fill(1);
  n[dim - 1] = cells + 1;
  last = n;
  first[dim - 1] = 1;
  Model<dim> m(Grid<dim>(origin, size, n));
  m.materials.push_back(std::make_shared<Hencky>(kE, 0.0, kRho));
  m.basis = basis;
  m.gravity[dim - 1] = -kG;
  add_regular_points<dim>(
      m.grid, first, last, ppc, [](const Vec<dim>&) { return true; }, 0, kRho, m.points);
  for (int node = 0; node < m.grid.num_nodes(); ++node) {
    const auto ijk = m.grid.node_ijk(node);
    if (ijk[dim - 1] <= 1)
      for (int c = 0; c < dim; ++c) m.constraints.push_back({node, c, 0.0});  // base (y <= 0) fixed
    for (int d = 0; d + 1 < dim; ++d)
      if (ijk[d] == 0 || ijk[d] == n[d]) m.constraints.push_back({node, d, 0.0});  // lateral rollers
  }
  return m;
}

struct ColumnErrors {
  double stress;     ///< max |sigma_yy - sigma_exact| / (rho0 g H0)
  double position;   ///< max |y - y_exact| / H0
  double stress_l2;  ///< sqrt(sum V_p (sigma_yy - sigma_exact)^2 / sum V_p) / (rho0 g H0)
};

template <int dim>
ColumnErrors column_errors(const Model<dim>& m) {
  const auto exact = column_closed_form();
  ColumnErrors e{0, 0, 0};
  double volume = 0;
  for (int p = 0; p < m.points.size(); ++p) {
    const double Y = m.points.original_position[p][dim - 1];
    const double ds = m.points.stress[p](dim - 1, dim - 1) - exact.cauchy_stress(Y);
    e.stress = std::max(e.stress, std::abs(ds));
    e.stress_l2 += ds * ds * m.points.original_volume[p];
    volume += m.points.original_volume[p];
    e.position = std::max(e.position, std::abs(m.points.position[p][dim - 1] - exact.position(Y)));
  }
  e.stress /= kRho * kG * kH0;
  e.stress_l2 = std::sqrt(e.stress_l2 / volume) / (kRho * kG * kH0);
  e.position /= kH0;
  return e;
}

/// The assembled tangent of a load step at a random iterate du (entries uniform in
/// [-amplitude, amplitude], seeded) against central differences of step h of its internal
/// force: max |K - K_fd| / max |K|, and K's asymmetry max |K - K^T| / max |K|. Leaves the
/// step's state at du.
struct TangentCheck {
  double error = 0.0, asymmetry = 0.0;
};
template <int dim>
TangentCheck assembled_tangent_check(detail::LoadStep<dim>& step, double amplitude, unsigned seed, double h) {
  const int n = step.dofs().num_dofs();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Vector du(n), f;
  for (int i = 0; i < n; ++i) du[i] = amplitude * u(rng);
  step.internal_force(du, f);
  const Eigen::MatrixXd Kd(step.stiffness());
  double err = 0.0;
  for (int j = 0; j < n; ++j) {
    Vector fp, fm, d = du;
    d[j] += h;
    step.internal_force(d, fp);
    d[j] -= 2 * h;
    step.internal_force(d, fm);
    err = std::max(err, ((fp - fm) / (2 * h) - Kd.col(j)).cwiseAbs().maxCoeff());
  }
  step.internal_force(du, f);
  const double scale = Kd.cwiseAbs().maxCoeff();
  return {err / scale, (Kd - Kd.transpose()).cwiseAbs().maxCoeff() / scale};
}

}  // namespace gradmpm::test
