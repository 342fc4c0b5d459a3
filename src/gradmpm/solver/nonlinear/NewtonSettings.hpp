#pragma once
// What the generic Newton solver (solver/nonlinear/Newton.hpp) is told and what it
// records: its settings, the seconds of its phases, and the ordering carried from one
// step's symbolic analysis to the next.
#include <string>
#include <vector>

#include "gradmpm/solver/linear/LinearSolverSettings.hpp"

namespace gradmpm {

/// Arc-length control ([arc_length]; NewtonSolver::solve_arc_length): the load factor is
/// found with the displacements, so a path past a limit point, and back (snap-back), can
/// be followed.
struct ArcLengthSettings {
  bool enabled = false;
  /// cylindrical: |du|^2 = l^2 over every dof (Crisfield 1981); relative displacement:
  /// u_to - u_from of one component grows by l each step (indirect displacement control,
  /// de Borst 1987), which follows a snap-back whose displacements retrace their way
  /// (elastic unloading around a softening zone) where the cylindrical arc cannot turn.
  /// displacement: the displacement of one node's component grows by l each step
  /// (displacement control of a load-driven problem: past its limit load).
  enum class Method { Cylindrical, RelativeDisplacement, Displacement } method = Method::Cylindrical;
  int from_node = -1, to_node = -1;  ///< relative displacement: the grid nodes; displacement: to_node
  int component = 0;                 ///< relative displacement: the component
  int max_steps = 100;              ///< the run stops after this many steps
  double initial_increment = 0.05;  ///< the first step's load factor (load control); its |du| is the first arc
  double max_load_factor = 1.0;     ///< the run stops once the load factor reaches this
  int target_iterations = 6;        ///< the arc grows or shrinks by sqrt(target / iterations) (by 2 at most)
};

struct NewtonSettings {
  int load_steps = 1;
  double tolerance = 1e-9;  ///< on |r_free| / max(|f_ext|, |f_int|)
  int max_iterations = 25;
  int max_cuts = 6;  ///< halvings of a failing load increment before giving up
  /// Backtracking on the residual: a correction that does not lower the out-of-balance
  /// force is halved until it does (at most kLineSearchHalvings times). It is what lets
  /// frictional contact settle partial slip, where the stick-slip switches of the points
  /// make full Newton corrections cycle; off, the iterates are Newton's own.
  bool line_search = false;
  /// A direct solver keeps its symbolic analysis for the next load step when that step's
  /// pattern is the same (the answer is the same to the bit; off only to test that).
  bool reuse_analysis = true;
  /// When the pattern has changed, the analysis takes the previous step's fill-reducing
  /// ordering, carried through the grid nodes, unless the pattern's entries changed by
  /// more than 10 % or the fill exceeds by 10 % that of the last ordering computed afresh
  /// (then it orders afresh): the ordering (AMD, METIS) is most of an analysis. The
  /// answer is the same to round-off (off only to test that).
  bool reuse_ordering = true;
  /// Where a load step's symbolic analysis runs: on the calling thread beside its first
  /// tangent's assembly on the other threads where the last measured analysis and
  /// tangent say it pays (Measured), always there (Always), or after the assembly (Never).
  /// The answer is the same to the bit (Always and Never only to test that).
  enum class AnalysisBeside { Measured, Always, Never } analysis_beside = AnalysisBeside::Measured;
  LinearSolverSettings linear_solver;
  ArcLengthSettings arc_length;
};

/// Seconds spent in each phase of a load step (summed over its Newton iterations).
struct PhaseTimes {
  double pattern = 0;   ///< shape functions, active nodes, sparsity pattern, f_ext
  double assembly = 0;  ///< point loop: material updates, f_int and tangent scatter-add
  double analysis = 0;  ///< symbolic factorisation (once per load step)
  double factor = 0;    ///< numeric factorisations
  double solve = 0;     ///< triangular solves
  double update = 0;    ///< mapping the increment to the points, updating their state
  double nonlocal = 0;  ///< regularised plasticity: the Helmholtz operator and the kappa_bar solves
  int iterations = 0;   ///< Newton iterations (linear solves)
  int analyses = 0;     ///< symbolic analyses (0 in a step whose pattern the previous step had)
  int orderings = 0;    ///< of which with an ordering computed afresh (the others took the previous step's)
  int beside = 0;       ///< of which beside the first tangent's assembly (NewtonSettings::analysis_beside)
  long krylov = 0;      ///< Krylov iterations of those solves (an iterative linear solver; 0 for a direct one)
  PhaseTimes& operator+=(const PhaseTimes& o) {
    pattern += o.pattern;
    assembly += o.assembly;
    analysis += o.analysis;
    factor += o.factor;
    solve += o.solve;
    update += o.update;
    nonlocal += o.nonlocal;
    iterations += o.iterations;
    analyses += o.analyses;
    orderings += o.orderings;
    beside += o.beside;
    krylov += o.krylov;
    return *this;
  }
};

/// The last analysis's ordering, which the next load step's analysis starts from
/// (NewtonSettings::reuse_ordering; empty for iterative solvers).
struct CarriedOrdering {
  std::vector<int> nodes;  ///< the grid nodes in the order their equations were eliminated
  double fill = 0.0;       ///< entries of the factor per entry of the matrix, of the last ordering computed afresh
  double entries = 0.0;    ///< the matrix's entries at the last analysis
};

/// What Newton records of one solve (StepInfo, the driver's record of a step, is one).
struct NewtonLog {
  std::vector<double> residuals;  ///< normalised out-of-balance force per Newton iteration
  PhaseTimes phases;              ///< of the converged attempt
  /// iterations whose symmetric tangent was not positive definite (solved by linear_solver.general)
  int indefinite_solves = 0;
  int backtracks = 0;  ///< halvings of Newton corrections that inverted a point (the converged attempt)
  int line_searches = 0;  ///< halvings of Newton corrections that raised the residual (NewtonSettings::line_search)
};

}  // namespace gradmpm
