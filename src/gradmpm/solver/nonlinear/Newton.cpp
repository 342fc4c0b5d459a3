#include "gradmpm/solver/nonlinear/Newton.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "gradmpm/core/Errors.hpp"
#include "gradmpm/core/Parallel.hpp"
#include "gradmpm/core/Timer.hpp"
#include "gradmpm/solver/Dirichlet.hpp"
#include "gradmpm/solver/linear/LinearSolver.hpp"

namespace gradmpm {

/// The linear solvers of the run. The pattern is fixed within a load step, so the symbolic
/// analysis is done once, however many Newton solves the step takes; and a direct solver
/// keeps it for the next step when that step's pattern is the same (points that stay in
/// their cells' supports: most steps of a small-strain run). The analysis depends on the
/// pattern only, so the answer is the same to the bit.
struct NewtonSolver::Solvers {
  std::unique_ptr<LinearSolver> main, general;  ///< general: made when a tangent is not positive definite
  bool analysed = false;                        ///< for this step's pattern
  bool general_analysed = false;                ///< general's analysis, for this step's pattern
  bool described = false;                       ///< describe() called with this step
  std::vector<int> outer, inner;                ///< the pattern main's analysis was made for
  /// Seconds of main's last analysis and of the last tangent assembled on all threads
  /// (0: none yet): whether the next analysis pays to run beside a tangent (beside()).
  double analysis_seconds = 0.0, tangent_seconds = 0.0;

  /// A new load step (or a new attempt of one).
  void start_step() { analysed = described = general_analysed = false; }
  /// After a failed attempt nothing is kept: the factor may be in any state.
  void forget() { *this = Solvers{}; }
  /// A converged step's factors are not solved with again: their memory goes to the
  /// gradient step and the next step (the analyses stay, LinearSolver::release_factor).
  void release_factors() {
    if (main) main->release_factor();
    if (general) general->release_factor();
  }
  /// Whether main's analysis was made for A's pattern (remembered only for direct solvers:
  /// an iterative one sets up again with each step's coordinates).
  bool analysed_for(const SparseMatrix& A) const {
    return static_cast<std::size_t>(A.outerSize()) + 1 == outer.size() &&
           static_cast<std::size_t>(A.nonZeros()) == inner.size() &&
           std::equal(outer.begin(), outer.end(), A.outerIndexPtr()) &&
           std::equal(inner.begin(), inner.end(), A.innerIndexPtr());
  }
  void remember_pattern(const SparseMatrix& A) {
    outer.assign(A.outerIndexPtr(), A.outerIndexPtr() + A.outerSize() + 1);
    inner.assign(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros());
  }

  /// The last analysis's ordering by grid node: each active node once, where its first
  /// equation is eliminated (empty for a solver without one). A later step's equations
  /// are numbered anew (nodes become active or inactive), its nodes are not.
  CarriedOrdering carried;

  void remember_ordering(const DofMap& dofs, const LinearSolver& solver) {
    const std::vector<int> perm = solver.ordering();
    std::vector<int>& node_order = carried.nodes;
    node_order.clear();
    if (perm.empty()) return;
    std::vector<char> seen(dofs.num_active_nodes(), 0);
    for (const int eq : perm) {
      const int local = eq / dofs.ncomp();
      if (!seen[local]) node_order.push_back(dofs.node_of(local));
      seen[local] = 1;
    }
  }
  /// Gives the solver the last ordering in this step's equations: the nodes still active
  /// in that order, each node's equations together, then the newly active ones.
  bool take_ordering(const DofMap& dofs, LinearSolver& solver) const {
    return !carried.nodes.empty() && solver.order_by(dofs.equations_in_node_order(carried.nodes));
  }
};

namespace {

/// Whether the symbolic analysis of A's pattern runs beside the tangent's assembly
/// (run_beside: the analysis on this thread, the assembly on the others). It pays where
/// an analysis is to be made (not an earlier step's kept), the solver's reads the pattern
/// only, and the tangent, assembled on one thread fewer, is expected to take no longer
/// than the two one after the other: with T threads, when the tangent's time on all of
/// them is below (T - 1) times the analysis's (the last of each, measured; none yet: no).
/// NewtonSettings::analysis_beside can say always or never.
/// At 1e5 dof in 2D on 2 threads the analysis takes two to three times a tangent's time;
/// where a tangent takes longer than twice the analysis (2 threads), the analysis follows it.
bool beside(const SparseMatrix& A, const LinearSolver& solver, const NewtonSolver::Solvers& solvers, bool share,
            NewtonSettings::AnalysisBeside mode) {
  using Mode = NewtonSettings::AnalysisBeside;
  if (mode == Mode::Never || share || !solver.analysis_reads_pattern_only() || !A.isCompressed()) return false;
  if (mode == Mode::Always) return true;
  if (solvers.analysis_seconds <= 0.0 || solvers.tangent_seconds <= 0.0) return false;
  return solvers.tangent_seconds < (max_threads() - 1) * solvers.analysis_seconds;
}

/// The symbolic analysis of the tangent's pattern (A's values are not read); the caller
/// has checked that the solver's analysis was not made for this pattern (an earlier step's). The previous step's
/// ordering is taken unless the pattern has grown or shrunk by more than a tenth (the
/// first step's regular points against moved ones: another graph), or the factor it gives
/// has more fill than a tenth above the last fresh ordering's (then the analysis is made
/// again, ordered afresh). Timed and counted in `times`.
void analyse(const SparseMatrix& A, const DofMap& dofs, LinearSolver& solver, NewtonSolver::Solvers& solvers,
             const NewtonSettings& settings, PhaseTimes& times) {
  const auto t0 = Clock::now();
  const double entries = static_cast<double>(A.nonZeros());
  CarriedOrdering& carried = solvers.carried;
  bool taken = settings.reuse_ordering && std::abs(entries - carried.entries) <= 0.1 * carried.entries &&
               solvers.take_ordering(dofs, solver);
  solver.analyze(A);
  ++times.analyses;
  carried.entries = entries;
  if (taken && solver.factor_nonzeros() > 1.1 * carried.fill * entries) {
    solver.analyze(A);  // a poor fit (points moved far, material entered new cells): afresh
    ++times.analyses;
    taken = false;
  }
  if (!taken) {
    ++times.orderings;
    carried.fill = solver.factor_nonzeros() / entries;
  }
  if (settings.reuse_ordering) solvers.remember_ordering(dofs, solver);
  if (settings.reuse_analysis && !solver.iterative()) solvers.remember_pattern(A);
  solvers.analysis_seconds = seconds_since(t0);
  times.analysis += seconds_since(t0);
}

/// Inexact Newton (Eisenstat & Walker 1996, choice 2, with their safeguard): an
/// iterative linear solver reduces the residual only as far as Newton's progress
/// warrants, eta_k = 0.9 (r_k / r_k-1)^2, at most 1e-2; and never below a tenth of what
/// the Newton tolerance asks of this iterate (no oversolving), so the last iterations keep
/// the quadratic rate to the tolerance. A direct solver ignores it.
double forcing_term(const std::vector<double>& residuals, double newton_tolerance, double previous) {
  constexpr double eta_max = 1e-2, gamma = 0.9;
  const std::size_t k = residuals.size() - 1;
  double eta = eta_max;
  if (k > 0 && residuals[k - 1] > 0.0) {
    const double ratio = residuals[k] / residuals[k - 1];
    eta = gamma * ratio * ratio;
    if (gamma * previous * previous > 0.1) eta = std::max(eta, gamma * previous * previous);
  }
  eta = std::max(eta, 0.1 * newton_tolerance / std::max(residuals[k], 1e-300));
  return std::clamp(eta, 1e-14, eta_max);
}

/// Where Newton stands within a load step.
struct NewtonState {
  Vector du;               ///< the step's increment so far
  Vector correction_free;  ///< the free part of the last Newton correction (backtracking halves it)
  std::vector<double> residuals, absolute_residuals;
  double eta = 1e-2;  ///< the forcing term of an iterative solver (forcing_term)
};

/// The out-of-balance force r at du (zero in constrained rows), relative to the forces
/// in balance, and absolute.
struct Residual {
  Vector r;
  double relative = 0.0, absolute = 0.0;
};

/// The residual at s.du, with backtracking to admissibility: a Newton correction that
/// inverts a point (det dF <= 0), or at which a material update fails (a non-finite
/// internal force), is halved on the free dofs only (the prescribed increments stay as
/// they are), up to kHalvings times before the step fails. Far from the solution (the
/// first iterates of a step that starts a mechanism) the full correction can overshoot by
/// far more than the increment itself; the step need not be cut for that.
Residual residual_at(NonlinearProblem& problem, NewtonState& s, bool first, NewtonLog& log) {
  constexpr int kHalvings = 8;
  for (int halving = 0;; ++halving) {
    std::string failure;
    Residual res;
    try {
      const ResidualNorms norms = problem.residual(s.du, res.r);  // (one reduction over the ranks)
      // A material update that failed at a distorted iterate (NaN stress; e.g. F-bar's
      // dF scaled by (dJbar / dJ)^(1/dim) at a point squeezed to dJ = 5e-9) makes the
      // norms NaN on every rank. Caught here: std::max(0, NaN) is 0, and the relative
      // residual was then 0, a NaN state taken as converged.
      if (std::isfinite(norms.scale) && std::isfinite(norms.residual)) {
        res.absolute = norms.residual;
        res.relative = norms.scale > 0.0 ? norms.residual / norms.scale : 0.0;
        return res;
      }
      failure = "the internal force is not finite (a material update failed at this iterate)";
    } catch (const StepFailure& f) {
      failure = f.reason;
    }
    if (first || halving == kHalvings) throw StepFailure{failure};
    s.correction_free *= 0.5;
    s.du -= s.correction_free;
    ++log.backtracks;
  }
}

/// NewtonSettings::line_search: while the residual at s.du is not below the last
/// iterate's (by a sufficient decrease, 1e-4 of it), the correction is halved, at most
/// kHalvings times; the last halving is kept whatever its residual (Newton goes on from
/// there). A point inverted at a halving takes residual_at's own halvings.
void search_line(NonlinearProblem& problem, NewtonState& s, Residual& res, NewtonLog& log) {
  constexpr int kHalvings = 6;
  constexpr double kSufficient = 1e-4;
  const double previous = s.residuals.back();
  for (int halving = 0; halving < kHalvings && res.relative > (1.0 - kSufficient) * previous; ++halving) {
    s.correction_free *= 0.5;
    s.du -= s.correction_free;
    ++log.line_searches;
    res = residual_at(problem, s, false, log);
  }
}

/// Converged: relative to the forces, or (after the first iterate) at the round-off of the
/// internal force, which a tiny strain cannot beat. `floor` is an estimate: on fine grids
/// with tiny increments the residual can stall a few times above it (the 1.0e5-dof biaxial
/// test at 1/2560 of its load: 1.1e-10 against 4.5e-11, for 25 iterations), so a residual
/// within kStall times the floor that is no longer halved in two iterations is round-off too.
bool newton_converged(const NewtonState& s, double tolerance, double floor) {
  constexpr double kStall = 10.0;
  const std::size_t it = s.residuals.size() - 1;
  const double absolute = s.absolute_residuals.back();
  const bool stalled = it >= 3 && absolute < kStall * floor && absolute > 0.5 * s.absolute_residuals[it - 2];
  return s.residuals.back() < tolerance || (it > 0 && absolute < floor) || stalled;
}

/// The step's linear solver, made at its first use (a non-symmetric tangent goes to a
/// general solver as it is: never symmetrised) and told what the system is. A distributed
/// run's tangent goes to the solver as each rank's share (its points' terms), which the
/// solver adds up by rows (PETSc), and each rank reads the solution in its own and ghost
/// rows only (step.halo()).
SystemDescription prepare_solver(NonlinearProblem& step, const NewtonSettings& settings, NewtonSolver::Solvers& solvers) {
  if (!solvers.main) {
    const MatrixKind kind = step.symmetric_tangent() ? MatrixKind::Symmetric : MatrixKind::General;
    solvers.main = make_linear_solver(settings.linear_solver, kind);
  }
  const bool share = solvers.main->adds_shares();
  const SystemDescription description{step.dofs().ncomp(), [&step] { return step.node_coordinates(); }, share,
                                      share ? &step.halo() : nullptr};
  if (!solvers.described) {
    solvers.main->describe(description);
    solvers.described = true;
  }
  return description;
}

/// The tangent at the last residual's iterate with the constrained rows eliminated, factorised:
/// solve() takes any right-hand side with its prescribed values (an arc-length iteration
/// solves two with one factor).
struct FactoredTangent {
  DirichletElimination bc;
  LinearSolver* solver = nullptr;  ///< the main solver, or the general one where K was not positive definite
  PhaseTimes* times = nullptr;
  /// The general solver factorised, for a main solver that fails to solve (an iterative
  /// one that does not converge on an indefinite K).
  std::function<LinearSolver&()> general;

  /// K d = b with d_c = `prescribed` (b is lifted in place).
  Vector solve(Vector& b, const std::vector<double>& prescribed) {
    bc.apply_to_rhs(b, prescribed);
    const auto t0 = Clock::now();
    const long krylov = solver->iterations();
    Vector d;
    try {
      try {
        d = solver->solve(b);
      } catch (const SolverError&) {
        if (solver->general()) throw;
        solver = &general();
        d = solver->solve(b);
      }
    } catch (const SolverError& e) {
      throw StepFailure{e.what()};
    }
    times->solve += seconds_since(t0);
    times->krylov += solver->iterations() - krylov;
    bc.impose(d, prescribed);
    return d;
  }
};

/// The general solver for a tangent the main solver finds not positive definite (a
/// distorted trial state, or a genuine instability): the symmetric indefinite system still
/// has a Newton step, which the general solver gives.
LinearSolver& factor_indefinite(const SparseMatrix& K, const NewtonSettings& settings, NewtonSolver::Solvers& solvers,
                                const SystemDescription& description) {
  auto& general = solvers.general;
  if (!general) general = make_linear_solver(settings.linear_solver, MatrixKind::General);
  if (description.shares && !general->adds_shares())
    throw SolverError(
        fmt::format("linear_solver.general = \"{}\" cannot solve a distributed run's tangent", general->name()));
  if (!solvers.general_analysed) {  // this step's pattern (a later step's may differ)
    general->describe(description);
    general->analyze(K);
    solvers.general_analysed = true;
  }
  general->factorize(K);
  return *general;
}

/// The tangent assembled (only now that another iteration follows) and analysed at the
/// step's first, the Dirichlet rows eliminated, factorised. `eta`: an iterative solver's
/// relative tolerance (forcing_term).
FactoredTangent factor_tangent(NonlinearProblem& step, const NewtonSettings& settings, NewtonSolver::Solvers& solvers,
                               const SystemDescription& description, double eta, NewtonLog& info) {
  PhaseTimes& times = info.phases;
  LinearSolver& solver = *solvers.main;
  SparseMatrix* tangent = nullptr;
  FactoredTangent out;
  out.times = &times;
  bool on_all_threads = true;  // (false: beside the analysis)
  const auto assemble = [&] {
    const auto t = Clock::now();
    tangent = &step.tangent(description.shares);
    const double seconds = seconds_since(t);
    times.assembly += seconds;
    if (on_all_threads) solvers.tangent_seconds = seconds;
    out.bc.apply_to_matrix(*tangent, step.constrained(), &step.halo(), true);  // make_pattern(): cliques, symmetric
  };
  // The pattern is fixed within the load step: analysed at its first tangent, unless the
  // solver's analysis was made for it (an earlier step's, kept).
  const bool analysis_due = !solvers.analysed && !solvers.analysed_for(step.pattern());
  const auto analyse_once = [&] {
    if (analysis_due) analyse(step.pattern(), step.dofs(), solver, solvers, settings, times);
    solvers.analysed = true;
  };
  try {
    // The symbolic analysis reads the pattern only, serially: where it pays (beside()), on
    // this thread while the others assemble the step's first tangent into the pattern's
    // values (a core idled through the analysis: 0.08 s of a load step at 1e5 dof in 2D).
    // The same analysis and tangent either way.
    if (analysis_due && beside(step.pattern(), solver, solvers, description.shares, settings.analysis_beside)) {
      on_all_threads = false;
      ++times.beside;
      run_beside(analyse_once, assemble);
    } else {
      assemble();
      analyse_once();
    }
    if (solver.iterative()) solver.set_relative_tolerance(eta);
    const auto t0 = Clock::now();
    out.general = [&, tangent]() -> LinearSolver& {
      ++info.indefinite_solves;
      return factor_indefinite(*tangent, settings, solvers, description);
    };
    try {
      solver.factorize(*tangent);
      out.solver = &solver;
    } catch (const SolverError&) {
      if (solver.general()) throw;
      out.solver = &out.general();
    }
    times.factor += seconds_since(t0);
    ++times.iterations;
  } catch (const SolverError& e) {
    throw StepFailure{e.what()};
  }
  return out;
}

/// One Newton correction added to s.du: K d = r with the `prescribed` increments.
void add_correction(NonlinearProblem& step, const NewtonSettings& settings, NewtonSolver::Solvers& solvers,
                    const SystemDescription& description, Residual& res, const std::vector<double>& prescribed,
                    NewtonState& s, NewtonLog& info) {
  if (solvers.main->iterative()) s.eta = forcing_term(s.residuals, settings.tolerance, s.eta);
  FactoredTangent K = factor_tangent(step, settings, solvers, description, s.eta, info);
  const Vector d = K.solve(res.r, prescribed);
  s.correction_free = d;
  for (int c : step.constrained()) s.correction_free[c] = 0.0;
  s.du += d;
}

}  // namespace

NewtonSolver::NewtonSolver() : solvers_(std::make_unique<Solvers>()) {}
NewtonSolver::~NewtonSolver() = default;
void NewtonSolver::start_step() { solvers_->start_step(); }
void NewtonSolver::forget() { solvers_->forget(); }
void NewtonSolver::release_factors() { solvers_->release_factors(); }
const CarriedOrdering& NewtonSolver::carried() const { return solvers_->carried; }
void NewtonSolver::set_carried(const CarriedOrdering& ordering) { solvers_->carried = ordering; }

Vector NewtonSolver::solve(NonlinearProblem& problem, const NewtonSettings& settings, NewtonLog& log,
                           const Vector* start) {
  Solvers& solvers = *solvers_;
  // The first iterate linearises about the converged state (du = 0) and brings the
  // prescribed increments in through the right-hand side: d_c = du_c, K_ff d_f = r_f - K_fc du_c.
  // (Starting from du_c on the boundary and 0 inside would ask the tangent of a distorted state.)
  NewtonState s;
  s.du = start ? *start : Vector::Zero(problem.dofs().num_dofs());
  const bool applied = start != nullptr;  // the prescribed increments are in du already
  const std::vector<double> zeros(problem.constrained().size(), 0.0);
  const SystemDescription description = prepare_solver(problem, settings, solvers);
  const double floor = problem.roundoff_force();
  constexpr double kDivergence = 1e6;  // a residual this many times the first's (or the tolerance) diverges
  for (int it = 0;; ++it) {
    const auto t0 = Clock::now();
    Residual res = residual_at(problem, s, it == 0, log);
    if (settings.line_search && it > 0) search_line(problem, s, res, log);
    log.phases.assembly += seconds_since(t0);
    double err = res.relative;
    // The prescribed increments not applied yet are out of balance too (every rank's).
    if (it == 0 && !applied && problem.largest_increment() > 0.0) err = std::max(err, 1.0);
    s.residuals.push_back(err);
    s.absolute_residuals.push_back(res.absolute);
    log.residuals.push_back(err);
    if (!std::isfinite(err)) throw StepFailure{"the out-of-balance force is not finite"};
    if (newton_converged(s, settings.tolerance, floor)) {
      problem.converged();
      return s.du;  // (a distributed run's: right in own and ghost rows)
    }
    if (it == settings.max_iterations)
      throw StepFailure{fmt::format("no convergence in {} iterations (residual {:.3e})", it, err)};
    if (it >= 2 && err > kDivergence * std::max(s.residuals.front(), settings.tolerance))
      throw StepFailure{fmt::format("Newton diverges (residual {:.3e})", err)};
    const std::vector<double>& prescribed = it == 0 && !applied ? problem.increments() : zeros;
    add_correction(problem, settings, solvers, description, res, prescribed, s, log);
  }
}

namespace {

/// The root x of a x^2 + b x + c = 0 (a > 0) that `better` prefers; StepFailure where there
/// is none (the arc misses the path: a turn sharper than the arc's length).
template <class Better>
double arc_root(double a, double b, double c, Better&& better) {
  const double disc = b * b - 4.0 * a * c;
  if (!(disc >= 0.0) || !(a > 0.0))
    throw StepFailure{"arc-length: the constraint has no real root (the path turns more sharply than the arc)"};
  const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));  // (no cancellation)
  const double x1 = q / a, x2 = q != 0.0 ? c / q : -x1;
  return better(x1, x2) ? x1 : x2;
}

}  // namespace

Vector NewtonSolver::solve_arc_length(ParametrisedProblem& problem, const NewtonSettings& settings, ArcLength& arc,
                                      NewtonLog& log) {
  Solvers& solvers = *solvers_;
  const std::vector<double> u_ref = problem.reference_increments();
  const std::vector<double> zeros(u_ref.size(), 0.0);
  const SystemDescription description = prepare_solver(problem, settings, solvers);
  const double floor = problem.roundoff_force();
  constexpr double kDivergence = 1e6;
  NewtonState s;
  s.du = Vector::Zero(problem.dofs().num_dofs());
  double dlambda = 0.0;
  for (int it = 0;; ++it) {
    problem.set_load_factor(arc.lambda_n + dlambda, dlambda);
    const auto t0 = Clock::now();
    Residual res;
    const ResidualNorms norms = problem.residual(s.du, res.r);
    log.phases.assembly += seconds_since(t0);
    const double err = norms.scale > 0.0 ? norms.residual / norms.scale : 0.0;
    if (!std::isfinite(err)) throw StepFailure{"the out-of-balance force is not finite"};
    s.residuals.push_back(err);
    s.absolute_residuals.push_back(norms.residual);
    log.residuals.push_back(err);
    // (the first iterate is the last step's balance: the predictor follows it)
    if (it > 0 && newton_converged(s, settings.tolerance, floor)) {
      problem.converged();
      arc.dlambda = dlambda;
      return s.du;
    }
    if (it == settings.max_iterations)
      throw StepFailure{fmt::format("no convergence in {} iterations (residual {:.3e})", it, err)};
    if (it >= 2 && err > kDivergence * std::max(s.residuals[1], settings.tolerance))
      throw StepFailure{fmt::format("Newton diverges (residual {:.3e})", err)};
    FactoredTangent K = factor_tangent(problem, settings, solvers, description, s.eta, log);
    Vector q = problem.reference_load();
    const Vector du_ref = K.solve(q, u_ref);        // the tangent displacement per unit load factor
    const Vector du_res = K.solve(res.r, zeros);    // the correction at a fixed load factor
    const Vector w = s.du + du_res;
    double x;
    if (!arc.linear.empty()) {  // c . (w + x du_ref) = length
      double cw = 0.0, cr = 0.0;
      for (const auto& [dof, weight] : arc.linear) {
        cw += weight * w[dof];
        cr += weight * du_ref[dof];
      }
      if (cr == 0.0) throw StepFailure{"arc-length: the controlled displacement does not move with the load"};
      x = (arc.length - cw) / cr;
      s.du = w + x * du_ref;
      dlambda += x;
      continue;
    }
    const double a = du_ref.squaredNorm(), b = 2.0 * du_ref.dot(w), c = w.squaredNorm() - arc.length * arc.length;
    if (it == 0) {  // the predictor: on along the path (Feng, Peric & Owen 1996: the previous increment's side)
      const double side = arc.previous ? arc.previous(du_ref) : 1.0;
      x = arc_root(a, b, c, [&](double x1, double) { return side >= 0.0 ? x1 >= 0.0 : x1 < 0.0; });
    } else {  // the root whose iterate turns least from the last
      const auto turn = [&](double r) { return (w + r * du_ref).dot(s.du); };
      x = arc_root(a, b, c, [&](double x1, double x2) { return turn(x1) >= turn(x2); });
    }
    s.du = w + x * du_ref;
    dlambda += x;
  }
}

}  // namespace gradmpm
