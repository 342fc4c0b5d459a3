#pragma once
// The gradient step of the Ru-Aifantis operator split (eq. 7 of the paper and its
// strain/stress analogues): given a classical field c, find g with
//     g - l^2 laplacian(g) = c,
// whose weak form on the grid is
//     (M + l^2 L) g = f,   M_ij = sum_p N_i N_j V_p,  L_ij = sum_p grad N_i . grad N_j V_p,
// with f_i = sum_p N_i c_p V_p for a field held at the points (e-RA, s-RA), or with
// c_p interpolated from the nodes (f = M c) for a nodal field (u-RA). Both operators are integrated by the material
// points, the same quadrature as the stiffness. The matrix is scalar (one unknown per node), factored once and reused
// for every component and every right-hand side. Without Dirichlet dofs the boundary condition is the natural one, grad
// g . n = 0.
#include <stdexcept>
#include <vector>

#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/solver/Assembler.hpp"
#include "gradmpm/solver/Dirichlet.hpp"
#include "gradmpm/solver/linear/LinearSolver.hpp"

namespace gradmpm {

template <int dim>
class HelmholtzSmoother {
 public:
  /// `scalar_pattern`: build_pattern() for one component per node. `dirichlet_dofs`:
  /// equations whose value is prescribed in every smoothing (u-RA); empty for natural BCs.
  /// `shares`: a distributed run's, where the assembler visits this rank's points and
  /// the pattern is their share (build_rank_pattern): the solver adds the ranks'
  /// matrices up, the loads are summed in this rank's own and ghost rows (RowHalo), and
  /// the smoothed fields are right in those rows (all that its points' stencils read);
  /// a rank's `dirichlet_dofs` are those of its own and ghost rows (it may hold none
  /// where another rank holds some: whether the system has any is decided over the ranks).
  /// `ordering`: an elimination order of the equations for its analysis
  /// (LinearSolver::order_by): another smoother's on the same pattern, taken as it is; or,
  /// with `compare`, one made for another system on these nodes (the load step's), kept
  /// only where its factor is cheaper than the solver's own ordering's. Empty: its own.
  HelmholtzSmoother(const Assembler<dim>& assembler, const SparseMatrix& scalar_pattern, double length_scale,
                    const std::vector<int>& dirichlet_dofs = {}, const LinearSolverSettings& solver = {},
                    bool shares = false, std::vector<int> ordering = {}, bool compare = false)
      : assembler_(assembler),
        solver_(make_linear_solver(solver)),
        halo_(shares ? RowHalo(assembler.dofs().rank_rows(), touched_rows(scalar_pattern), assembler.dofs().global_rows()) : RowHalo()),
        held_(shares ? ranks::any(!dirichlet_dofs.empty()) : !dirichlet_dofs.empty()) {
    if (shares && !solver_->adds_shares())
      throw std::logic_error("a distributed run's Helmholtz system needs a solver that adds the ranks' shares");
    SparseMatrix A = scalar_pattern;
    assembler.add_helmholtz(A, length_scale * length_scale);
    if (held_) dirichlet_.apply_to_matrix(A, dirichlet_dofs, &halo_, true);  // build_pattern(): symmetric
    SystemDescription system;  // scalar, factorised once
    system.factorized_once = true;
    if (shares) {
      system.shares = true;
      system.halo = &halo_;
    }
    solver_->describe(system);
    solver_->order_by(std::move(ordering), compare);
    solver_->compute(A);
  }
  // The solver and the Dirichlet elimination keep the halo's address.
  HelmholtzSmoother(const HelmholtzSmoother&) = delete;
  HelmholtzSmoother& operator=(const HelmholtzSmoother&) = delete;

  /// Smooths a field known at the points (e-RA: a strain component, s-RA: a stress one).
  Vector smooth_point_field(const std::vector<double>& c_at_points,
                            const std::vector<double>& dirichlet_values = {}) const {
    return solve(assembler_.load(c_at_points), dirichlet_values);
  }

  /// Natural-boundary smoothing of several fields at once: column j of `f` is the load
  /// of field j (Assembler::load_columns; with shares, of this rank's points); one solve
  /// sweep serves all.
  Eigen::MatrixXd smooth_loads(Eigen::MatrixXd f) const {
    halo_.sum(f);  // with shares: own and ghost rows (every column with one exchange)
    return solver_->solve(f);
  }

  /// Seconds its sparse solver has taken in factorisation and solves (not the analysis).
  double solver_seconds() const { return solver_->seconds(); }
  /// Its sparse solver (its ordering, its timings).
  const LinearSolver& solver() const { return *solver_; }

  /// Smooths a nodal field (u-RA: a displacement component): f_i = sum_p N_i c(x_p) V_p,
  /// which is M c with M integrated by the points.
  Vector smooth_nodal_field(const Vector& c, const std::vector<double>& dirichlet_values = {}) const {
    return solve(assembler_.load(assembler_.interpolate(c)), dirichlet_values);
  }

 private:
  Vector solve(Vector f, const std::vector<double>& dirichlet_values) const {
    halo_.sum(f);  // with shares, this rank's points' load: summed in own and ghost rows
    if (held_) dirichlet_.apply_to_rhs(f, dirichlet_values);
    return solver_->solve(f);
  }

  const Assembler<dim>& assembler_;
  DirichletElimination dirichlet_;
  std::unique_ptr<LinearSolver> solver_;
  RowHalo halo_;  ///< with shares, this rank's own and ghost rows (else every row, no exchange)
  bool held_;     ///< some value is prescribed (on some rank's rows)
};

}  // namespace gradmpm
