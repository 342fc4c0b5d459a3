#include "gradmpm/app/BarProblem.hpp"

#include "gradmpm/basis/LinearBasis.hpp"
#include "gradmpm/core/Timer.hpp"
#include "gradmpm/gradient/Helmholtz.hpp"
#include "gradmpm/grid/Grid.hpp"
#include "gradmpm/points/Generate.hpp"
#include "gradmpm/points/Transfer.hpp"
#include "gradmpm/solver/Assembler.hpp"
#include "gradmpm/solver/Dirichlet.hpp"

namespace gradmpm {

namespace {

/// eps_p = sum_a dN_a/dx u_a : the strain of a nodal displacement at every point.
std::vector<double> point_strains(const PointStencils<1>& st, const Vector& u) {
  std::vector<double> eps(st.size());
  for (std::size_t p = 0; p < st.size(); ++p) {
    double e = 0.0;
    for (int a = 0; a < st[p].count; ++a) e += st[p].dN[a][0] * u[st[p].node[a]];
    eps[p] = e;
  }
  return eps;
}

/// The bar's axial modulus: the xx-xx entry of the material's tangent (E for nu = 0).
double axial_modulus(const Material& m) {
  std::vector<double> state_n(m.state_size()), state(m.state_size());
  m.initial_state(state_n.data());
  MaterialResponse r;
  m.update(Mat3::Identity(), state_n.data(), state.data(), r);
  Mat9 A;
  m.tangent(r, 1, A);
  return A(0, 0);
}
/// sigma_p = law(eps_p): the constitutive update at every point (axial strain only).
std::vector<double> point_stresses(const BarResult& r, const std::vector<double>& eps) {
  std::vector<double> sig(eps.size());
  MaterialResponse resp;
  std::vector<double> state_n, state;
  for (std::size_t p = 0; p < eps.size(); ++p) {
    Mat3 dF = Mat3::Identity();
    dF(0, 0) += eps[p];
    const Material& m = r.materials[r.points.material[p]];
    state_n.resize(m.state_size());
    state.resize(m.state_size());
    m.initial_state(state_n.data());
    m.update(dF, state_n.data(), state.data(), resp);
    sig[p] = resp.stress(0, 0);
  }
  return sig;
}
/// eps_p = sigma_p / E_p (s-RA: the strain that goes with a smoothed stress).
std::vector<double> point_compliant_strains(const BarResult& r, const std::vector<double>& sig) {
  std::vector<double> eps(sig.size());
  for (std::size_t p = 0; p < sig.size(); ++p) eps[p] = sig[p] / r.point_young[p];
  return eps;
}

/// Displacement compatible with a strain field held at the points, u(0) = 0:
/// minimises integral (u' - eps)^2, i.e. L u = sum_p dN eps_p V_p. In 1D this is the
/// exact integral u(x) = integral_0^x eps at the nodes (for e-RA and s-RA, which
/// smooth strain or stress and have no displacement of their own).
Vector integrate_strain(const Assembler<1>& assembler, const SparseMatrix& pattern, const std::vector<double>& eps,
                        int left_dof, const LinearSolverSettings& backend) {
  SparseMatrix L = pattern;
  assembler.add_laplacian(L);
  DirichletElimination bc;
  bc.apply_to_matrix(L, {left_dof});
  Vector f = assembler.gradient_load(eps, 0);
  bc.apply_to_rhs(f, {0.0});
  const auto solver = make_linear_solver(backend);
  solver->compute(L);
  return solver->solve(f);
}
}  // namespace

BarResult solve_bar(const BarConfig& c) {
  BarResult r;
  const auto t_assembly = Clock::now();

  // Background grid = the 1D mesh; material points at the Gauss positions of each cell.
  const Grid<1> grid(Vec<1>(0.0), Vec<1>(c.length / c.elements), {c.elements});
  const double x_interface = c.split * c.length;
  add_gauss_points<1>(
      grid, {0}, {c.elements}, c.points_per_element, [&](const Vec<1>& x) { return x[0] < x_interface ? 0 : 1; },
      r.points);
  r.materials = {LinearElastic(c.young_left, 0.0, 0.0), LinearElastic(c.young_right, 0.0, 0.0)};
  const double moduli[2] = {axial_modulus(r.materials[0]), axial_modulus(r.materials[1])};
  for (int m : r.points.material) r.point_young.push_back(moduli[m]);

  const PointStencils<1> st = evaluate_stencils<1, LinearBasis<1>>(grid, r.points);
  const DofMap dofs(st, grid.num_nodes(), 1);
  const SparseMatrix pattern = build_pattern(st, dofs);
  const Assembler<1> assembler(st, r.points, dofs, &grid);
  r.dofs = dofs.num_dofs();

  // Classical problem: K_ab = sum_p dN_a E_p dN_b V_p, u(0) = 0, u(L) = delta.
  SparseMatrix K = pattern;
  assembler.add_matrix(K, [&](int p, const Stencil<1>& s, Assembler<1>::LocalMatrix& Ke) {
    const double w = r.point_young[p] * r.points.volume[p];
    for (int a = 0; a < s.count; ++a)
      for (int b = 0; b < s.count; ++b) Ke(a, b) += w * s.dN[a][0] * s.dN[b][0];
  });
  const std::vector<int> ends = {dofs.dof(0, 0), dofs.dof(grid.num_nodes() - 1, 0)};
  const std::vector<double> end_values = {0.0, c.end_displacement};
  DirichletElimination bc;
  bc.apply_to_matrix(K, ends);
  Vector f = Vector::Zero(dofs.num_dofs());
  bc.apply_to_rhs(f, end_values);
  r.timings.assembly_s = seconds_since(t_assembly);

  const auto t_solve = Clock::now();
  const auto solver = make_linear_solver(c.solver);
  solver->compute(K);
  r.u_classical = dofs.to_grid(solver->solve(f));
  r.timings.classical_solve_s = seconds_since(t_solve);

  r.point_strain_classical = point_strains(st, r.u_classical);
  r.point_stress_classical = point_stresses(r, r.point_strain_classical);

  // Gradient step: one factorisation of (M + l^2 L) per analysis, natural boundaries
  // unless the variant smooths displacements (u-RA copies the classical Dirichlet data).
  const auto t_gradient = Clock::now();
  Vector strain_nodes, stress_nodes;  // nodal values the variant solves for directly
  switch (c.variant) {
    case GradientVariant::None:
      r.u_gradient = r.u_classical;
      r.point_strain_gradient = r.point_strain_classical;
      r.point_stress_gradient = r.point_stress_classical;
      break;
    case GradientVariant::U_RA: {
      const HelmholtzSmoother<1> smoother(assembler, pattern, c.length_scale, ends, c.solver);
      r.u_gradient = dofs.to_grid(smoother.smooth_nodal_field(r.u_classical, end_values));
      r.point_strain_gradient = point_strains(st, r.u_gradient);
      r.point_stress_gradient = point_stresses(r, r.point_strain_gradient);
      break;
    }
    case GradientVariant::E_RA:
    case GradientVariant::S_RA: {
      // The smoothed field (strain for e-RA, stress for s-RA) with natural boundaries,
      // the other from the law at the points.
      const bool strain = c.variant == GradientVariant::E_RA;
      const HelmholtzSmoother<1> smoother(assembler, pattern, c.length_scale, {}, c.solver);
      const Vector smoothed = smoother.smooth_point_field(strain ? r.point_strain_classical : r.point_stress_classical);
      (strain ? strain_nodes : stress_nodes) = dofs.to_grid(smoothed);
      const std::vector<double> at_points = assembler.interpolate(smoothed);
      r.point_strain_gradient = strain ? at_points : point_compliant_strains(r, at_points);
      r.point_stress_gradient = strain ? point_stresses(r, at_points) : at_points;
      break;
    }
  }
  r.timings.gradient_s = seconds_since(t_gradient);

  const auto t_recovery = Clock::now();
  if (c.variant == GradientVariant::E_RA || c.variant == GradientVariant::S_RA)
    r.u_gradient = dofs.to_grid(integrate_strain(assembler, pattern, r.point_strain_gradient, ends[0], c.solver));

  // Nodal values: the smoothed field itself where the variant solves for it, else the
  // volume-weighted recovery of the point values (points/Transfer.hpp).
  const int nn = grid.num_nodes();
  for (int n = 0; n < nn; ++n) r.x.push_back(grid.node_position(n)[0]);
  r.strain_classical = points_to_nodes(st, r.points, r.point_strain_classical, nn);
  r.stress_classical = points_to_nodes(st, r.points, r.point_stress_classical, nn);
  r.strain_gradient = strain_nodes.size() ? strain_nodes : points_to_nodes(st, r.points, r.point_strain_gradient, nn);
  r.stress_gradient = stress_nodes.size() ? stress_nodes : points_to_nodes(st, r.points, r.point_stress_gradient, nn);

  const double h = grid.cell_size()[0];
  for (int e = 0; e < c.elements; ++e) {
    r.element_midpoint.push_back((e + 0.5) * h);
    r.element_strain_classical.push_back((r.u_classical[e + 1] - r.u_classical[e]) / h);
    r.element_strain_gradient.push_back((r.u_gradient[e + 1] - r.u_gradient[e]) / h);
  }
  r.timings.recovery_s = seconds_since(t_recovery);
  return r;
}

}  // namespace gradmpm
