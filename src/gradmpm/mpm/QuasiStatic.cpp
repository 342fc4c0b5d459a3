#include "gradmpm/mpm/QuasiStatic.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

#include "gradmpm/core/Errors.hpp"
#include "gradmpm/core/Parallel.hpp"
#include "gradmpm/core/Timer.hpp"
#include "gradmpm/mpm/Consolidation.hpp"
#include "gradmpm/mpm/Dynamics.hpp"
#include "gradmpm/mpm/GradientCoupling.hpp"
#include "gradmpm/mpm/ImplicitGradient.hpp"
#include "gradmpm/mpm/LoadStep.hpp"
#include "gradmpm/mpm/RankPoints.hpp"
#include "gradmpm/solver/nonlinear/Newton.hpp"

namespace gradmpm {

namespace {

/// A load factor (a time) this close to its end, relative to it, is the end: the sum of
/// the increments carries round-off.
constexpr double kEndTolerance = 1e-12;

using detail::ConsolidationStep;
using detail::DynamicStep;
using detail::GradientCouplingStep;
using detail::LoadStep;

/// The load step's equilibrium: one solve, or with regularised plasticity the staggered
/// iteration of mpm/ImplicitGradient.hpp: the solve with kappa_bar frozen, then kappa_bar =
/// (M + l^2 L)^-1 M kappa of the converged iterate (Anderson-accelerated), written into the
/// state the step starts from, until kappa_bar stops changing. `solve(start)`: a Newton or
/// an arc-length solve of the whole step (the same arc from the same state each pass),
/// from `start` (null: from du = 0).
template <int dim, class Solve>
Vector staggered_solve(LoadStep<dim>& step, Model<dim>& model, const NewtonSettings& settings, StepInfo& info,
                       NewtonSolver& newton, Solve&& solve) {
  newton.start_step();
  if (!NonlocalPlasticStrain<dim>::applies(model)) return solve(nullptr);
  const auto t0 = Clock::now();
  NonlocalPlasticStrain<dim> nonlocal(model, step.stencils(), settings.linear_solver);
  if (!model.regularisation.start_from_points) nonlocal.smooth(model.points.state, model.points.state);
  info.phases.nonlocal += seconds_since(t0);
  Vector du = solve(nullptr);
  for (int k = 1;; ++k) {
    const auto t1 = Clock::now();
    const double change = nonlocal.iterate(step.trial_state(), model.points.state);
    info.phases.nonlocal += seconds_since(t1);
    ++info.staggers;
    du = solve(&du);
    // Both fields in balance: kappa_bar moved by less than the tolerance, and the
    // displacements are in balance with it. (That Newton needed no correction at the new
    // kappa_bar is not enough: a uniform change of stress leaves a 1D bar in balance
    // while kappa, and so G(kappa_bar), has changed.)
    if (change <= model.regularisation.tolerance) return du;
    if (k == model.regularisation.max_iterations)
      throw StepFailure{fmt::format("the nonlocal plastic strain did not converge in {} staggered iterations", k)};
  }
}

/// The step's equilibrium by Newton on `problem` (the load step, or its dynamic or u-p
/// wrapper), the next pass starting from the last one's du.
template <int dim>
Vector solve_step(LoadStep<dim>& step, NonlinearProblem& problem, Model<dim>& model, const NewtonSettings& settings,
                  StepInfo& info, NewtonSolver& newton) {
  return staggered_solve(step, model, settings, info, newton,
                         [&](const Vector* start) { return newton.solve(problem, settings, info, start); });
}

/// An arc-length step's equilibrium: each pass an arc-length solve of the whole step.
template <int dim>
Vector solve_arc_step(LoadStep<dim>& step, Model<dim>& model, const NewtonSettings& settings, StepInfo& info,
                      NewtonSolver& newton, NewtonSolver::ArcLength& arc) {
  return staggered_solve(step, model, settings, info, newton,
                         [&](const Vector*) { return newton.solve_arc_length(step, settings, arc, info); });
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

namespace {

/// What a run advances in steps: the load factor lambda from 0 to 1 in load steps
/// (quasi-static), or the time t from 0 to end_time in time steps, the loads following
/// lambda(t) (dynamics, TimeSettings).
/// With arc-length control the load factor is not chosen but found: the increment
/// advanced is the arc's length, and the run ends after max_steps, at max_load_factor, or
/// once the load has fallen back to 0.
struct StepControl {
  const TimeSettings& time;
  const ArcLengthSettings& arc;
  double end, nominal;  ///< where the run ends, and the nominal increment
  StepControl(const TimeSettings& t, const NewtonSettings& s)
      : time(t),
        arc(s.arc_length),
        end(t.dynamic() ? t.end_time : s.arc_length.enabled ? s.arc_length.max_load_factor : 1.0),
        nominal(t.dynamic() ? t.dt : s.arc_length.enabled ? s.arc_length.initial_increment : 1.0 / s.load_steps) {}
  double load_factor(double tau) const { return time.dynamic() ? time.load_factor(tau) : tau; }
  bool reached(double tau) const { return end - tau < kEndTolerance * end; }
  /// Arc-length: whether the run ends after `steps` steps at load factor lambda, the
  /// largest so far `peak`.
  bool arc_done(int steps, double lambda, double peak) const {
    return steps >= arc.max_steps || reached(lambda) || (peak > 0.0 && lambda <= 0.0);
  }
};

/// The next arc's length after a converged step that took `iterations`: by Newton's
/// effort, never longer than the first arc (`nominal`: the resolution the user asked for).
double next_arc(const ArcLengthSettings& arc, double length, int iterations, double nominal) {
  const double ratio = std::sqrt(static_cast<double>(arc.target_iterations) / std::max(iterations, 1));
  return std::min(length * std::clamp(ratio, 0.5, 2.0), nominal);
}

/// The kinetic energy of every rank's points.
template <int dim>
double kinetic_energy(const Model<dim>& model) {
  double e = 0.0;
  for (int p = 0; p < model.points.size(); ++p) e += 0.5 * model.points.mass[p] * model.points.velocity[p].squaredNorm();
  if (ranks::distributed()) ranks::sum(&e, 1);
  return e;
}

/// Indirect displacement control's constraint: u_to - u_from of the component, as
/// (equation, weight) pairs of the step's numbering.
std::vector<std::pair<int, double>> relative_displacement(const ArcLengthSettings& arc, const DofMap& dofs) {
  const bool single = arc.method == ArcLengthSettings::Method::Displacement;
  for (const int node : {arc.from_node, arc.to_node})
    if (!(single && node == arc.from_node) && !dofs.active(node))
      throw UserError(fmt::format("[arc_length]: grid node {} (arc_length.{}) is in no point's stencil: choose a "
                                  "point inside the body",
                                  node, single ? "at" : "from or .to"));
  if (single) return {{dofs.dof(arc.to_node, arc.component), 1.0}};
  return {{dofs.dof(arc.to_node, arc.component), 1.0}, {dofs.dof(arc.from_node, arc.component), -1.0}};
}

/// One attempt of the step from tau to tau + dtau: the load step (with the inertia of a
/// dynamic one) solved and committed to the points, whose ranks are then brought up to
/// date. Throws StepFailure (the caller cuts dtau), or SolverError where no cut can help.
/// `arc`: an arc-length step from load factor tau (dtau unused; its increment comes back
/// in arc->dlambda).
template <int dim>
Vector attempt_step(Model<dim>& model, const NewtonSettings& settings, const StepControl& control, double tau,
                    double dtau, bool initial, const std::vector<PostStepStage<dim>*>& stages, NewtonSolver& newton,
                    std::unique_ptr<LoadStep<dim>>& step, StepInfo& info, int number,
                    NewtonSolver::ArcLength* arc = nullptr) {
  auto t0 = Clock::now();
  step.reset();
  if (arc) dtau = 0.0;  // (the step is made at lambda_n; Newton moves it)
  const double lambda = control.load_factor(tau), lambda_end = control.load_factor(tau + dtau);
  try {  // (a distributed run: on this rank's points)
    // (quasi-static: dtau itself, not (tau + dtau) - tau, which differs from it in the last bits)
    const double dlambda = model.time.dynamic() ? lambda_end - lambda : dtau;
    step = std::make_unique<LoadStep<dim>>(model, lambda_end, dlambda);
  } catch (const std::out_of_range& e) {  // points left the grid: no cut can help
    throw SolverError(model.time.dynamic()
                          ? fmt::format("time step {} (t = {:.6g}): {}", number, tau, e.what())
                          : fmt::format("load step {} (load factor {:.6g}): {}", number, lambda, e.what()));
  }
  std::unique_ptr<DynamicStep<dim>> dynamic;
  if (model.time.inertial())
    dynamic = std::make_unique<DynamicStep<dim>>(*step, model, dtau, lambda, lambda_end, initial,
                                                 settings.linear_solver);
  std::unique_ptr<ConsolidationStep<dim>> pore;  // the pore pressure beside du (mpm/Consolidation.hpp)
  if (model.pore.active())
    pore = std::make_unique<ConsolidationStep<dim>>(*step, model, model.time.dynamic() ? dtau : 0.0, lambda_end);
  info.phases.pattern = seconds_since(t0);
  // Regularised plasticity solved monolithically: kappa_bar beside du (mpm/GradientCoupling.hpp).
  std::unique_ptr<NonlocalPlasticStrain<dim>> nonlocal;
  std::unique_ptr<GradientCouplingStep<dim>> coupled;
  if (model.regularisation.monolithic && NonlocalPlasticStrain<dim>::applies(model)) {
    const auto t1 = Clock::now();
    nonlocal = std::make_unique<NonlocalPlasticStrain<dim>>(model, step->stencils(), settings.linear_solver);
    coupled = std::make_unique<GradientCouplingStep<dim>>(*step, model, *nonlocal);
    info.phases.nonlocal += seconds_since(t1);
  }
  NonlinearProblem& problem = dynamic   ? static_cast<NonlinearProblem&>(*dynamic)
                              : pore    ? static_cast<NonlinearProblem&>(*pore)
                              : coupled ? static_cast<NonlinearProblem&>(*coupled)
                                        : *step;
  info.dofs = problem.dofs().num_global_dofs();
  info.nonzeros = problem.pattern().nonZeros();
  Vector du;
  if (arc) {
    arc->linear.clear();  // (a linear constraint in this step's equations)
    if (settings.arc_length.method != ArcLengthSettings::Method::Cylindrical)
      arc->linear = relative_displacement(settings.arc_length, step->dofs());
    du = solve_arc_step(*step, model, settings, info, newton, *arc);
  } else if (coupled) {
    newton.start_step();
    du = coupled->commit(newton.solve(problem, settings, info, nullptr));  // (the displacement part)
  } else {
    du = solve_step(*step, problem, model, settings, info, newton);
  }
  t0 = Clock::now();
  if (pore) {
    auto grid_p = std::make_shared<const Vector>(pore->grid_pressure(du));
    info.grid_pore_pressure = [grid_p]() -> const Vector& { return *grid_p; };
    du = pore->commit(model, du);  // the points' p; the displacement part goes on
  }
  step->commit(model, du);
  if (dynamic) {
    dynamic->commit(model, du);
    info.inertia_ratio = dynamic->inertia_ratio();
  }
  info.migrated = migrate_to_owners(model, stages);  // points now in another rank's cells go to it
  if (ranks::distributed()) {
    double moved = info.migrated;
    ranks::sum(&moved, 1);
    info.migrated = static_cast<int>(moved);
  }
  info.phases.update = seconds_since(t0);
  step->release_newton_data();
  newton.release_factors();
  return du;
}

/// The step's grid fields for the outputs, made on the first call (a collective call).
template <int dim>
void offer_grid_fields(StepInfo& info, const Model<dim>& model, const LoadStep<dim>& step, const Vector& du,
                       std::optional<typename LoadStep<dim>::GridFields>& grid) {
  const auto fields = [&]() -> const typename LoadStep<dim>::GridFields& {
    if (!grid) grid = step.grid_fields(du);
    return *grid;
  };
  info.grid_nodes = [fields] { return fields().nodes; };
  info.grid_displacement = [fields]() -> const Vector& { return fields().displacement; };  // (no whole-grid copy per caller)
  info.grid_reaction = [fields]() -> const Vector& { return fields().reaction; };
  info.grid_mass = [fields]() -> const Vector& { return fields().mass; };
  info.grid_active = [&model, &step] {
    std::vector<bool> active(model.grid.num_nodes());
    for (int n = 0; n < model.grid.num_nodes(); ++n) active[n] = step.dofs().active(n);
    return active;
  };
  info.rigid_forces = [&step] { return step.rigid_forces(); };
}

}  // namespace

namespace {

/// Where a run stands between its steps (what a checkpoint records, DriverState).
/// tau: the load factor, or a dynamic run's time; dtau its next increment, or the next arc.
struct Progress {
  double tau = 0.0, dtau = 0.0;
  double peak_kinetic = 0.0, peak_lambda = 0.0;
  std::vector<double> previous;  ///< arc-length: the last increment at the grid nodes
  double arc_nominal = 0.0;      ///< arc-length: the first arc

  Progress(const DriverState& start, const StepControl& control)
      : tau(control.time.dynamic() ? start.time : start.load_factor),
        dtau(start.next_increment > 0.0 ? start.next_increment : control.nominal),
        peak_kinetic(start.peak_kinetic_energy),
        peak_lambda(start.peak_load_factor),
        previous(start.arc_previous),
        arc_nominal(start.arc_nominal) {}

  /// A dynamic step's time, kinetic energy and whether it ends at rest: little kinetic
  /// energy, and not at the turning point of an oscillation (where the velocity vanishes
  /// but the acceleration does not).
  template <int dim>
  void record_dynamics(const Model<dim>& model, StepInfo& info) {
    info.time = tau;
    info.time_increment = dtau;
    info.kinetic_energy = kinetic_energy(model);
    peak_kinetic = std::max(peak_kinetic, info.kinetic_energy);
    const double rest = model.time.stop_at_rest;
    info.at_rest = rest > 0.0 && peak_kinetic > 0.0 && info.kinetic_energy <= rest * peak_kinetic &&
                   info.inertia_ratio <= std::sqrt(rest);
  }

  /// The next increment: back towards the nominal after a cut; arc-length: the first
  /// step's length is the first arc, later arcs follow Newton's effort.
  void next(const StepControl& control, const DofMap& dofs, const Vector& du, bool arc_step, const StepInfo& info) {
    const ArcLengthSettings& arc = control.arc;
    if (!arc.enabled) {
      if (info.cuts == 0) dtau = std::min(2.0 * dtau, control.nominal);
      return;
    }
    const Vector at_nodes = dofs.to_grid_all(du);
    previous.assign(at_nodes.data(), at_nodes.data() + at_nodes.size());
    if (arc_step) {
      // (Newton's effort per solve: regularised plasticity's staggered passes solve again)
      const int passes = info.staggers + 1;
      if (info.cuts == 0) dtau = next_arc(arc, dtau, (info.phases.iterations + passes - 1) / passes, arc_nominal);
      return;
    }
    const bool linear = arc.method != ArcLengthSettings::Method::Cylindrical;
    double length = du.norm();
    if (linear) {
      length = 0.0;
      for (const auto& [dof, weight] : relative_displacement(arc, dofs)) length += weight * du[dof];
    }
    if (!(length > 0.0))
      throw UserError(fmt::format(
          "[arc_length]: the controlled {} did not grow in the first step ({:.3g}); choose arc_length.from and .to "
          "across the zone that opens (or arc_length.at and .component where the load pushes)",
          linear ? "relative displacement" : "displacement", length));
    dtau = arc_nominal = length;
  }

  DriverState state(const StepControl& control, const RunSummary& summary, const CarriedOrdering& ordering) const {
    const bool dynamic = control.time.dynamic();
    return DriverState{.load_factor = control.load_factor(tau),
                       .next_increment = dtau,
                       .time = dynamic ? tau : 0.0,
                       .peak_kinetic_energy = peak_kinetic,
                       .arc_previous = previous,
                       .arc_nominal = arc_nominal,
                       .peak_load_factor = peak_lambda,
                       .summary = summary,
                       .ordering = ordering};
  }
};

/// The step from progress.tau, its increment halved where it fails (max_cuts times, then
/// SolverError); returns the converged du, with the step kept in `step`.
template <int dim>
Vector solve_with_cuts(Model<dim>& model, const NewtonSettings& settings, const StepControl& control,
                       Progress& progress, const std::vector<PostStepStage<dim>*>& stages, NewtonSolver& newton,
                       std::unique_ptr<LoadStep<dim>>& step, StepInfo& info, RunSummary& summary,
                       NewtonSolver::ArcLength* arc) {
  const bool dynamic = model.time.dynamic();
  // The staggered iteration writes kappa_bar into the state the step starts from: a cut
  // step starts again from the converged state's.
  const std::vector<double> committed =
      NonlocalPlasticStrain<dim>::applies(model) ? model.points.state : std::vector<double>{};
  const bool initial = model.time.inertial() && summary.steps == 0 && progress.tau == 0.0;
  while (true) {
    static_cast<NewtonLog&>(info) = NewtonLog{};
    info.staggers = 0;
    try {
      if (arc) arc->length = progress.dtau;
      return attempt_step(model, settings, control, progress.tau, progress.dtau, initial, stages, newton, step, info,
                          summary.steps + 1, arc);
    } catch (const StepFailure& f) {
      newton.forget();
      if (info.cuts == settings.max_cuts)
        throw SolverError(fmt::format("{} step {} failed from {} {:.6g} with increment {:.3g} after {} cut(s): {}",
                                      dynamic ? "time" : "load", summary.steps + 1, dynamic ? "time" : "load factor",
                                      progress.tau, progress.dtau, info.cuts, f.reason));
      if (!committed.empty()) model.points.state = committed;
      info.cut_reasons.push_back(fmt::format("increment {:.3g}: {}", progress.dtau, f.reason));
      progress.dtau *= 0.5;
      ++info.cuts;
      ++summary.cuts;
    }
  }
}

}  // namespace

template <int dim>
RunSummary run_quasi_static(Model<dim>& model, const NewtonSettings& settings,
                            const std::vector<PostStepStage<dim>*>& stages, const StepObserver<dim>& observer,
                            const DriverState& start) {
  RunSummary summary = start.summary;
  if (!model.state_initialised()) model.initialise_state();
  own_rank_points(model, stages);  // a distributed run: each rank its points (mpm/RankPoints.hpp)
  const StepControl control(model.time, settings);
  const bool dynamic = model.time.dynamic(), arc_length = settings.arc_length.enabled;
  if (arc_length && ranks::distributed()) throw UserError("[arc_length] runs on one rank");
  if (model.pore.active() && (model.time.inertial() || arc_length || ranks::distributed()))
    throw UserError("pore pressure runs on one rank, without inertia or arc-length control");
  if (model.pore.active() && model.pore.fluids.size() != model.materials.size())
    throw std::logic_error("PoreSettings::fluids needs one fluid per material");
  Progress progress(start, control);
  double& tau = progress.tau;
  NewtonSolver newton;  // across the steps: an unchanged pattern keeps its analysis, a changed one its ordering
  newton.set_carried(start.ordering);
  const auto done = [&] { return arc_length ? control.arc_done(summary.steps, tau, progress.peak_lambda) : control.reached(tau); };
  while (!done()) {
    // Arc-length: the first step is load-controlled; its |du| is the first arc.
    const bool arc_step = arc_length && !progress.previous.empty();
    if (!arc_step) progress.dtau = std::min(progress.dtau, control.end - tau);
    StepInfo info;
    std::unique_ptr<LoadStep<dim>> step;  // kept for the grid fields the observer may ask for
    NewtonSolver::ArcLength arc;
    arc.lambda_n = tau;
    arc.previous = [&](const Vector& v) {
      const auto& previous = progress.previous;
      return step->dofs().to_grid_all(v).dot(Eigen::Map<const Vector>(previous.data(), previous.size()));
    };
    const auto t0 = Clock::now();
    const Vector du = solve_with_cuts(model, settings, control, progress, stages, newton, step, info, summary,
                                      arc_step ? &arc : nullptr);
    const double advanced = arc_step ? arc.dlambda : progress.dtau;
    tau += advanced;
    if (control.reached(tau) && !arc_step) tau = control.end;
    info.step = ++summary.steps;
    info.load_factor = control.load_factor(tau);
    info.increment = dynamic ? control.load_factor(tau) - control.load_factor(tau - progress.dtau) : advanced;
    if (dynamic) progress.record_dynamics(model, info);
    info.seconds = seconds_since(t0);
    progress.peak_lambda = std::max(progress.peak_lambda, info.load_factor);
    info.last = done() || info.at_rest;
    std::optional<typename LoadStep<dim>::GridFields> grid;
    offer_grid_fields(info, model, *step, du, grid);
    summary.total_iterations += info.phases.iterations;
    progress.next(control, step->dofs(), du, arc_step, info);
    info.after = progress.state(control, summary, newton.carried());
    const auto t_stages = Clock::now();
    for (PostStepStage<dim>* stage : stages) stage->after_step(model, info);
    info.stage_seconds = seconds_since(t_stages);
    if (observer) observer(model, info);
    if (info.at_rest) break;
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
