#pragma once
// Newton-Raphson on any NonlinearProblem (solver/nonlinear/NonlinearProblem.hpp): the
// residual at the iterate (backtracking to an admissible one), the tangent assembled only
// when another iteration follows, the Dirichlet rows eliminated, K d = r solved, until the
// relative residual is below the tolerance or at the round-off of the forces.
//
// The solver keeps its linear solvers from step to step: the pattern is fixed within a
// step, so the symbolic analysis is made once per step (or kept, when the next step's
// pattern is the same), and the fill-reducing ordering is carried to the next step's
// analysis through the grid nodes (NewtonSettings::reuse_analysis, reuse_ordering).
#include <functional>
#include <memory>

#include "gradmpm/solver/nonlinear/NewtonSettings.hpp"
#include "gradmpm/solver/nonlinear/NonlinearProblem.hpp"

namespace gradmpm {

class NewtonSolver {
 public:
  NewtonSolver();
  ~NewtonSolver();
  NewtonSolver(const NewtonSolver&) = delete;
  NewtonSolver& operator=(const NewtonSolver&) = delete;

  /// A new step (or a new attempt of one): its pattern is analysed at its first tangent,
  /// unless the last analysis was made for the same pattern.
  void start_step();
  /// After a failed attempt nothing is kept: a factor may be in any state.
  void forget();
  /// A converged step's factors are not solved with again: their memory goes to the next
  /// step (the analyses stay).
  void release_factors();
  /// What the next analysis starts from (a restart sets the checkpoint's).
  const CarriedOrdering& carried() const;
  void set_carried(const CarriedOrdering& ordering);

  /// The solution du of the step's problem; throws StepFailure (no convergence in
  /// settings.max_iterations, divergence, a singular tangent, an iterate that cannot be
  /// evaluated after backtracking). The first iterate linearises about du = 0 and brings
  /// the prescribed values in through the right-hand side. `start`: a solution of the
  /// same step to start from (the prescribed values in it), as a staggered scheme's
  /// later passes do. Appends to `log`.
  Vector solve(NonlinearProblem& problem, const NewtonSettings& settings, NewtonLog& log,
               const Vector* start = nullptr);

  /// One step of the arc-length method (Crisfield 1981, cylindrical, or a linear
  /// constraint: indirect displacement control, de Borst 1987): the load factor is
  /// an unknown beside du, and each iterate keeps |du|^2 = length^2 (du with its
  /// prescribed values, u_ref per unit load factor). Each iteration solves K with two
  /// right-hand sides, the residual and f_ref, and takes the root of the constraint's
  /// quadratic nearer the last iterate (the larger du . du_k); the predictor goes the way
  /// `previous` says (its dot product with the step's tangent displacement: negative
  /// after a limit point; none: increasing load). No real root or no convergence: StepFailure.
  struct ArcLength {
    double lambda_n = 0.0;  ///< the load factor the step starts from
    double length = 0.0;    ///< the arc's length
    /// du . (the previous step's increment), for the predictor's direction; empty: none.
    std::function<double(const Vector&)> previous;
    /// Indirect displacement control instead of the cylindrical arc: the constraint
    /// c . du = length, c given as (local dof, weight) pairs; empty: cylindrical.
    std::vector<std::pair<int, double>> linear;
    double dlambda = 0.0;   ///< out: the step's load-factor increment
  };
  Vector solve_arc_length(ParametrisedProblem& problem, const NewtonSettings& settings, ArcLength& arc,
                          NewtonLog& log);

  /// The linear solvers and what is kept of their analyses (Newton.cpp).
  struct Solvers;

 private:
  std::unique_ptr<Solvers> solvers_;
};

}  // namespace gradmpm
