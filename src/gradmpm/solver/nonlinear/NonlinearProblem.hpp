#pragma once
// The seam between Newton and the physics: what the generic Newton solver
// (solver/nonlinear/Newton.hpp) sees of one step's nonlinear system R(du) = 0. The MPM's
// load step (mpm/LoadStep.hpp) is one; implicit dynamics (mpm/Dynamics.hpp) wraps it and
// adds the inertia of the points; a step controller (load, time, arc-length) makes one
// per step and hands it to Newton. Newton owns the iteration: line search (backtracking to
// admissible iterates), the linear solvers and their symbolic analyses, the inexact-Newton
// forcing term, and the convergence test; the problem owns the residual and the tangent.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "gradmpm/core/Types.hpp"
#include "gradmpm/solver/DofMap.hpp"
#include "gradmpm/solver/RowHalo.hpp"

namespace gradmpm {

/// A Newton failure inside one step (the step controller cuts the increment): an iterate
/// the physics cannot evaluate (an inverted point, a failed material update), no
/// convergence, divergence, a singular tangent.
struct StepFailure {
  std::string reason;
};

/// The sizes the convergence test needs: |r| and the force scale it is measured against
/// (with a distributed run's: over every rank's own rows).
struct ResidualNorms {
  double residual = 0.0;  ///< |r| over the free rows
  double scale = 0.0;     ///< the larger of the forces in balance (|f_ext|, |f_int|, |M a|)
};

class NonlinearProblem {
 public:
  virtual ~NonlinearProblem() = default;

  /// The equations: a distributed run's local numbering (own and ghost rows), their halo,
  /// and the nodes' coordinates (an algebraic multigrid's near null space).
  virtual const DofMap& dofs() const = 0;
  virtual const RowHalo& halo() const = 0;
  virtual Eigen::MatrixXd node_coordinates() const = 0;
  /// The constrained equations and their prescribed values in this step.
  virtual const std::vector<int>& constrained() const = 0;
  virtual const std::vector<double>& increments() const = 0;
  /// The largest prescribed value (in size) over every rank's.
  virtual double largest_increment() const = 0;

  /// The out-of-balance force r(du) (zero in the constrained rows) and its norms; throws
  /// StepFailure where du cannot be evaluated (Newton then backtracks). Remembers the
  /// state at du for tangent() and converged().
  virtual ResidualNorms residual(const Vector& du, Vector& r) = 0;
  /// -dr/ddu at the last residual()'s du, in pattern()'s pattern (a distributed run's:
  /// this rank's share when `share`). The problem's own matrix, assembled in place.
  virtual SparseMatrix& tangent(bool share) = 0;
  virtual const SparseMatrix& pattern() const = 0;
  virtual bool symmetric_tangent() const = 0;
  /// The residual the arithmetic cannot resolve (Newton stops below it).
  virtual double roundoff_force() const = 0;
  /// The last residual()'s du is the solution: keep what the outputs need (reactions).
  virtual void converged() = 0;
};

/// A problem whose loads and prescribed values are proportional to a load factor lambda,
/// which the arc-length method (NewtonSolver::solve_arc_length) finds with the
/// displacements: f_ext = lambda f_ref, and the prescribed increments of a step from
/// lambda_n are (lambda - lambda_n) u_ref.
class ParametrisedProblem : public NonlinearProblem {
 public:
  /// The load factor at the step's end and its increment over the step.
  virtual void set_load_factor(double lambda_end, double dlambda) = 0;
  /// f_ref: df_ext / dlambda (a distributed run's: right in own and ghost rows).
  virtual const Vector& reference_load() = 0;
  /// u_ref: the prescribed values per unit load factor, in constrained() order.
  virtual const std::vector<double>& reference_increments() const = 0;
};

}  // namespace gradmpm
