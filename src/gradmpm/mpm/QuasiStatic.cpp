#include "gradmpm/mpm/QuasiStatic.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

#include "gradmpm/core/Errors.hpp"
#include "gradmpm/core/Parallel.hpp"
#include "gradmpm/core/Timer.hpp"
#include "gradmpm/mpm/ImplicitGradient.hpp"
#include "gradmpm/mpm/LoadStep.hpp"
#include "gradmpm/mpm/RankPoints.hpp"
#include "gradmpm/solver/Dirichlet.hpp"
#include "gradmpm/solver/linear/LinearSolver.hpp"

namespace gradmpm {

namespace {

/// A load factor this close to 1 is 1: the sum of the increments carries round-off.
constexpr double kLoadFactorEnd = 1e-12;

using detail::LoadStep;
using detail::StepFailure;

/// The linear solvers of the run. The pattern is fixed within a load step, so the symbolic
/// analysis is done once, however many Newton solves the step takes; and a direct solver
/// keeps it for the next step when that step's pattern is the same (points that stay in
/// their cells' supports: most steps of a small-strain run). The analysis depends on the
/// pattern only, so the answer is the same to the bit.
struct StepSolvers {
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
  void forget() { *this = StepSolvers{}; }
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

/// Whether the symbolic analysis of A's pattern runs beside the tangent's assembly
/// (run_beside: the analysis on this thread, the assembly on the others). It pays where
/// an analysis is to be made (not an earlier step's kept), the solver's reads the pattern
/// only, and the tangent, assembled on one thread fewer, is expected to take no longer
/// than the two one after the other: with T threads, when the tangent's time on all of
/// them is below (T - 1) times the analysis's (the last of each, measured; none yet: no).
/// NewtonSettings::analysis_beside can say always or never.
/// At 1e5 dof in 2D on 2 threads the analysis takes two to three times a tangent's time;
/// where a tangent takes longer than twice the analysis (2 threads), the analysis follows it.
bool beside(const SparseMatrix& A, const LinearSolver& solver, const StepSolvers& solvers, bool share,
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
void analyse(const SparseMatrix& A, const DofMap& dofs, LinearSolver& solver, StepSolvers& solvers,
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
  Vector f_int;            ///< the internal force at du
  Vector correction_free;  ///< the free part of the last Newton correction (backtracking halves it)
  std::vector<double> residuals, absolute_residuals;
  double eta = 1e-2;  ///< the forcing term of an iterative solver (forcing_term)
};

/// The out-of-balance force r = f_ext - f_int at du (zero in constrained rows), relative
/// to the larger of the two forces, and absolute.
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
template <int dim>
Residual residual_at(LoadStep<dim>& step, NewtonState& s, bool first, StepInfo& info) {
  constexpr int kHalvings = 8;
  for (int halving = 0;; ++halving) {
    std::string failure;
    try {
      step.internal_force(s.du, s.f_int);
    } catch (const StepFailure& f) {
      failure = f.reason;
    }
    if (failure.empty()) {
      Residual res{step.f_ext() - s.f_int};
      for (int c : step.constrained()) res.r[c] = 0.0;
      const auto [f_ext_norm, f_int_norm, r_norm] = step.norms(s.f_int, res.r);  // (one reduction over the ranks)
      // A material update that failed at a distorted iterate (NaN stress; e.g. F-bar's
      // dF scaled by (dJbar / dJ)^(1/dim) at a point squeezed to dJ = 5e-9) makes the
      // norms NaN on every rank. Caught here: std::max(0, NaN) is 0, and the relative
      // residual was then 0, a NaN state taken as converged.
      if (std::isfinite(f_ext_norm) && std::isfinite(f_int_norm) && std::isfinite(r_norm)) {
        const double scale = std::max(f_ext_norm, f_int_norm);
        res.absolute = r_norm;
        res.relative = scale > 0.0 ? r_norm / scale : 0.0;
        return res;
      }
      failure = "the internal force is not finite (a material update failed at this iterate)";
    }
    if (first || halving == kHalvings) throw StepFailure{failure};
    s.correction_free *= 0.5;
    s.du -= s.correction_free;
    ++info.backtracks;
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
template <int dim>
SystemDescription prepare_solver(LoadStep<dim>& step, const NewtonSettings& settings, StepSolvers& solvers) {
  if (!solvers.main) {
    const MatrixKind kind = step.symmetric_tangent() ? MatrixKind::Symmetric : MatrixKind::General;
    solvers.main = make_linear_solver(settings.linear_solver, kind);
  }
  const bool share = solvers.main->adds_shares();
  const SystemDescription description{dim, [&step] { return step.node_coordinates(); }, share,
                                      share ? &step.halo() : nullptr};
  if (!solvers.described) {
    solvers.main->describe(description);
    solvers.described = true;
  }
  return description;
}

/// K d = r where the main solver finds K not positive definite (a distorted trial state,
/// or a genuine instability): the symmetric indefinite system still has a Newton step,
/// which the general solver gives.
Vector solve_indefinite(const SparseMatrix& K, const Vector& r, const NewtonSettings& settings, StepSolvers& solvers,
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
  return general->solve(r);
}

/// One Newton correction added to s.du: the tangent assembled (only now that another
/// iteration follows) and analysed at the step's first, the Dirichlet rows eliminated
/// with the `prescribed` increments, K d = r solved.
template <int dim>
void add_correction(LoadStep<dim>& step, const NewtonSettings& settings, StepSolvers& solvers,
                    const SystemDescription& description, Residual& res, const std::vector<double>& prescribed,
                    NewtonState& s, StepInfo& info) {
  PhaseTimes& times = info.phases;
  LinearSolver& solver = *solvers.main;
  SparseMatrix* tangent = nullptr;
  DirichletElimination bc;
  bool on_all_threads = true;  // (false: beside the analysis)
  const auto assemble = [&] {
    const auto t = Clock::now();
    tangent = &step.stiffness(description.shares);
    const double seconds = seconds_since(t);
    times.assembly += seconds;
    if (on_all_threads) solvers.tangent_seconds = seconds;
    bc.apply_to_matrix(*tangent, step.constrained(), &step.halo(), true);  // make_pattern(): cliques, symmetric
  };
  // The pattern is fixed within the load step: analysed at its first tangent, unless the
  // solver's analysis was made for it (an earlier step's, kept).
  const bool analysis_due = !solvers.analysed && !solvers.analysed_for(step.pattern());
  const auto analyse_once = [&] {
    if (analysis_due) analyse(step.pattern(), step.dofs(), solver, solvers, settings, times);
    solvers.analysed = true;
  };
  const auto add = [&](const Vector& d) {
    Vector exact = d;
    bc.impose(exact, prescribed);
    s.correction_free = exact;
    for (int c : step.constrained()) s.correction_free[c] = 0.0;
    s.du += exact;
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
    SparseMatrix& K = *tangent;
    bc.apply_to_rhs(res.r, prescribed);
    if (solver.iterative()) {
      s.eta = forcing_term(s.residuals, settings.tolerance, s.eta);
      solver.set_relative_tolerance(s.eta);
    }
    auto t0 = Clock::now();
    try {
      solver.factorize(K);
      times.factor += seconds_since(t0);
      t0 = Clock::now();
      const long krylov = solver.iterations();
      add(solver.solve(res.r));
      times.solve += seconds_since(t0);
      times.krylov += solver.iterations() - krylov;
    } catch (const SolverError&) {
      if (solver.general()) throw;
      t0 = Clock::now();
      add(solve_indefinite(K, res.r, settings, solvers, description));
      times.factor += seconds_since(t0);
      ++info.indefinite_solves;
    }
    ++times.iterations;
  } catch (const SolverError& e) {
    throw StepFailure{e.what()};
  }
}

/// Newton-Raphson for one load step; returns the converged increment or throws
/// StepFailure. `start`: a converged increment of the same step to start from (a later
/// staggered iteration of regularised plasticity), the prescribed increments in it.
template <int dim>
Vector newton(LoadStep<dim>& step, const NewtonSettings& settings, StepSolvers& solvers, StepInfo& info,
              const Vector* start = nullptr) {
  // The first iterate linearises about the converged state (du = 0) and brings the
  // prescribed increments in through the right-hand side: d_c = du_c, K_ff d_f = r_f - K_fc du_c.
  // (Starting from du_c on the boundary and 0 inside would ask the tangent of a distorted state.)
  NewtonState s;
  s.du = start ? *start : Vector::Zero(step.dofs().num_dofs());
  const bool applied = start != nullptr;  // the prescribed increments are in du already
  const std::vector<double> zeros(step.constrained().size(), 0.0);
  const SystemDescription description = prepare_solver(step, settings, solvers);
  const double floor = step.roundoff_force();
  constexpr double kDivergence = 1e6;  // a residual this many times the first's (or the tolerance) diverges
  for (int it = 0;; ++it) {
    const auto t0 = Clock::now();
    Residual res = residual_at(step, s, it == 0, info);
    info.phases.assembly += seconds_since(t0);
    double err = res.relative;
    // The prescribed increments not applied yet are out of balance too (every rank's).
    if (it == 0 && !applied && step.largest_increment() > 0.0) err = std::max(err, 1.0);
    s.residuals.push_back(err);
    s.absolute_residuals.push_back(res.absolute);
    info.residuals.push_back(err);
    if (!std::isfinite(err)) throw StepFailure{"the out-of-balance force is not finite"};
    if (newton_converged(s, settings.tolerance, floor)) {
      step.converged(s.f_int);
      return s.du;  // (a distributed run's: right in own and ghost rows)
    }
    if (it == settings.max_iterations)
      throw StepFailure{fmt::format("no convergence in {} iterations (residual {:.3e})", it, err)};
    if (it >= 2 && err > kDivergence * std::max(s.residuals.front(), settings.tolerance))
      throw StepFailure{fmt::format("Newton diverges (residual {:.3e})", err)};
    const std::vector<double>& prescribed = it == 0 && !applied ? step.increments() : zeros;
    add_correction(step, settings, solvers, description, res, prescribed, s, info);
  }
}

/// The load step's equilibrium: one Newton solve, or with regularised plasticity the
/// staggered iteration of mpm/ImplicitGradient.hpp: Newton with kappa_bar frozen, then
/// kappa_bar = (M + l^2 L)^-1 M kappa of the converged iterate (Anderson-accelerated),
/// written into the state the step starts from, until kappa_bar stops changing.
template <int dim>
Vector solve_step(LoadStep<dim>& step, Model<dim>& model, const NewtonSettings& settings, StepInfo& info,
                  StepSolvers& solvers) {
  solvers.start_step();
  if (!NonlocalPlasticStrain<dim>::applies(model)) return newton(step, settings, solvers, info);
  const auto t0 = Clock::now();
  NonlocalPlasticStrain<dim> nonlocal(model, step.stencils(), settings.linear_solver);
  if (!model.regularisation.start_from_points) nonlocal.smooth(model.points.state, model.points.state);
  info.phases.nonlocal += seconds_since(t0);
  Vector du = newton(step, settings, solvers, info);
  for (int k = 1;; ++k) {
    const auto t1 = Clock::now();
    const double change = nonlocal.iterate(step.trial_state(), model.points.state);
    info.phases.nonlocal += seconds_since(t1);
    ++info.staggers;
    du = newton(step, settings, solvers, info, &du);
    // Both fields in balance: kappa_bar moved by less than the tolerance, and the
    // displacements are in balance with it. (That Newton needed no correction at the new
    // kappa_bar is not enough: a uniform change of stress leaves a 1D bar in balance
    // while kappa, and so G(kappa_bar), has changed.)
    if (change <= model.regularisation.tolerance) return du;
    if (k == model.regularisation.max_iterations)
      throw StepFailure{fmt::format("the nonlocal plastic strain did not converge in {} staggered iterations", k)};
  }
}

/// Moves the model's points and the stages' per-point arrays as `migration` says.
template <int dim>
void apply(const PointMigration& migration, Model<dim>& model, const std::vector<PostStepStage<dim>*>& stages) {
  migrate_points(model, migration);
  for (PostStepStage<dim>* stage : stages) stage->migrate(migration);
}

/// Sends this rank's point p to rank to[p] (a collective call); returns how many went to another rank.
template <int dim>
int send_points(const std::vector<int>& to, Model<dim>& model, const std::vector<PostStepStage<dim>*>& stages) {
  const PointMigration move = PointMigration::exchange(to, model.point_ids);
  apply(move, model, stages);
  return move.sent();
}

}  // namespace

template <int dim>
void own_rank_points(Model<dim>& model, const std::vector<PostStepStage<dim>*>& stages) {
  if (!ranks::distributed() || !model.rank_boxes.empty()) return;  // (owned: the reader made this rank's only)
  model.rank_boxes = rank_boxes(model.grid, model.points.original_position, ranks::size());
  const std::vector<int> rank = owners(model);
  std::vector<int> mine;
  for (int p = 0; p < model.points.size(); ++p)
    if (rank[p] == ranks::rank()) mine.push_back(p);
  apply(PointMigration::keep(std::move(mine)), model, stages);
}

template <int dim>
int migrate_to_owners(Model<dim>& model, const std::vector<PostStepStage<dim>*>& stages) {
  return ranks::distributed() ? send_points(owners(model), model, stages) : 0;
}

template <int dim>
void collect_on_root(Model<dim>& model, const std::vector<PostStepStage<dim>*>& stages) {
  if (ranks::distributed()) send_points(std::vector<int>(model.points.size(), 0), model, stages);
}

template <int dim>
void arrange_by_id(Model<dim>& model, const std::vector<PostStepStage<dim>*>& stages) {
  if (!ranks::distributed()) return;
  double total = model.points.size();
  ranks::sum(&total, 1);
  const long long n = static_cast<long long>(total), size = ranks::size();
  std::vector<int> to(model.points.size());
  for (std::size_t p = 0; p < to.size(); ++p) to[p] = static_cast<int>(model.point_ids[p] * size / n);
  send_points(to, model, stages);
}

template <int dim>
RunSummary run_quasi_static(Model<dim>& model, const NewtonSettings& settings,
                            const std::vector<PostStepStage<dim>*>& stages, const StepObserver<dim>& observer,
                            const DriverState& start) {
  RunSummary summary = start.summary;
  if (!model.state_initialised()) model.initialise_state();
  own_rank_points(model, stages);  // a distributed run: each rank its points (mpm/RankPoints.hpp)
  const double nominal = 1.0 / settings.load_steps;
  double lambda = start.load_factor, dlambda = start.next_increment > 0.0 ? start.next_increment : nominal;
  StepSolvers solvers;  // across the steps: an unchanged pattern keeps its analysis, a changed one its ordering
  solvers.carried = start.ordering;
  while (lambda < 1.0 - kLoadFactorEnd) {
    dlambda = std::min(dlambda, 1.0 - lambda);
    StepInfo info;
    std::unique_ptr<LoadStep<dim>> step;  // kept for the grid fields the observer may ask for
    Vector du;
    const auto t0 = Clock::now();
    // The staggered iteration writes kappa_bar into the state the step starts from: a cut
    // step starts again from the converged state's.
    const std::vector<double> committed =
        NonlocalPlasticStrain<dim>::applies(model) ? model.points.state : std::vector<double>{};
    while (true) {
      info.residuals.clear();
      info.phases = PhaseTimes{};
      info.staggers = 0;
      info.indefinite_solves = 0;
      info.backtracks = 0;
      try {
        auto t0 = Clock::now();
        step.reset();
        try {  // (a distributed run: on this rank's points)
          step = std::make_unique<LoadStep<dim>>(model, lambda + dlambda, dlambda);
        } catch (const std::out_of_range& e) {  // points left the grid: no cut can help
          throw SolverError(fmt::format("load step {} (load factor {:.6g}): {}", summary.steps + 1, lambda, e.what()));
        }
        info.phases.pattern = seconds_since(t0);
        info.dofs = step->dofs().num_global_dofs();
        info.nonzeros = step->pattern().nonZeros();
        du = solve_step(*step, model, settings, info, solvers);
        t0 = Clock::now();
        step->commit(model, du);
        info.migrated = migrate_to_owners(model, stages);  // points now in another rank's cells go to it
        if (ranks::distributed()) {
          double moved = info.migrated;
          ranks::sum(&moved, 1);
          info.migrated = static_cast<int>(moved);
        }
        info.phases.update = seconds_since(t0);
        step->release_newton_data();
        solvers.release_factors();
        break;
      } catch (const StepFailure& f) {
        solvers.forget();
        if (info.cuts == settings.max_cuts)
          throw SolverError(
              fmt::format("load step {} failed from load factor {:.6g} with increment {:.3g} after {} cut(s): {}",
                          summary.steps + 1, lambda, dlambda, info.cuts, f.reason));
        if (!committed.empty()) model.points.state = committed;
        info.cut_reasons.push_back(fmt::format("increment {:.3g}: {}", dlambda, f.reason));
        dlambda *= 0.5;
        ++info.cuts;
        ++summary.cuts;
      }
    }
    lambda += dlambda;
    if (1.0 - lambda < kLoadFactorEnd) lambda = 1.0;
    info.step = ++summary.steps;
    info.load_factor = lambda;
    info.increment = dlambda;
    info.seconds = seconds_since(t0);
    info.last = lambda >= 1.0;
    std::optional<typename LoadStep<dim>::GridFields> grid;  // made on the first call (collective)
    const auto fields = [&]() -> const typename LoadStep<dim>::GridFields& {
      if (!grid) grid = step->grid_fields(du);
      return *grid;
    };
    info.grid_nodes = [&] { return fields().nodes; };
    info.grid_displacement = [&]() -> const Vector& { return fields().displacement; };  // (no whole-grid copy per caller)
    info.grid_reaction = [&]() -> const Vector& { return fields().reaction; };
    info.grid_mass = [&]() -> const Vector& { return fields().mass; };
    info.grid_active = [&] {
      std::vector<bool> active(model.grid.num_nodes());
      for (int n = 0; n < model.grid.num_nodes(); ++n) active[n] = step->dofs().active(n);
      return active;
    };
    info.rigid_forces = [&] { return step->rigid_forces(); };
    summary.total_iterations += info.phases.iterations;
    if (info.cuts == 0) dlambda = std::min(2.0 * dlambda, nominal);  // grow back after a cut
    info.after = DriverState{lambda, dlambda, summary, solvers.carried};
    const auto t_stages = Clock::now();
    for (PostStepStage<dim>* stage : stages) stage->after_step(model, info);
    info.stage_seconds = seconds_since(t_stages);
    if (observer) observer(model, info);
  }
  return summary;
}

#define GRADMPM_OWNERSHIP(dim)                                                                   \
  template void own_rank_points<dim>(Model<dim>&, const std::vector<PostStepStage<dim>*>&);    \
  template int migrate_to_owners<dim>(Model<dim>&, const std::vector<PostStepStage<dim>*>&);   \
  template void collect_on_root<dim>(Model<dim>&, const std::vector<PostStepStage<dim>*>&);    \
  template void arrange_by_id<dim>(Model<dim>&, const std::vector<PostStepStage<dim>*>&);
GRADMPM_OWNERSHIP(1)
GRADMPM_OWNERSHIP(2)
GRADMPM_OWNERSHIP(3)
#undef GRADMPM_OWNERSHIP

template RunSummary run_quasi_static<1>(Model<1>&, const NewtonSettings&, const std::vector<PostStepStage<1>*>&,
                                        const StepObserver<1>&, const DriverState&);
template RunSummary run_quasi_static<2>(Model<2>&, const NewtonSettings&, const std::vector<PostStepStage<2>*>&,
                                        const StepObserver<2>&, const DriverState&);
template RunSummary run_quasi_static<3>(Model<3>&, const NewtonSettings&, const std::vector<PostStepStage<3>*>&,
                                        const StepObserver<3>&, const DriverState&);

}  // namespace gradmpm
