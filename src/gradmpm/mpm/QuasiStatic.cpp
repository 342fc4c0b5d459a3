#include "gradmpm/mpm/QuasiStatic.hpp"

#include <fmt/format.h>

#include <cmath>
#include <map>

#include "gradmpm/core/Errors.hpp"
#include "gradmpm/core/Parallel.hpp"
#include "gradmpm/core/Timer.hpp"
#include "gradmpm/mpm/LoadStep.hpp"
#include "gradmpm/solver/Dirichlet.hpp"
#include "gradmpm/solver/linear/LinearSolver.hpp"

namespace gradmpm {

namespace {

using detail::LoadStep;
using detail::StepFailure;

/// Newton-Raphson for one load step; returns the converged increment or throws StepFailure.
template <int dim>
Vector newton(LoadStep<dim>& step, const NewtonSettings& settings, std::vector<double>& residuals, int& indefinite,
              PhaseTimes& times) {
  // The first iterate linearises about the converged state (du = 0) and brings the
  // prescribed increments in through the right-hand side: d_c = du_c, K_ff d_f = r_f - K_fc du_c.
  // (Starting from du_c on the boundary and 0 inside would ask the tangent of a distorted state.)
  Vector du = Vector::Zero(step.dofs().num_dofs());
  const std::vector<double> zeros(step.constrained().size(), 0.0);
  // A non-symmetric tangent goes to a general solver as it is: never symmetrised.
  const MatrixKind kind = step.symmetric_tangent() ? MatrixKind::Symmetric : MatrixKind::General;
  const auto solver = make_linear_solver(settings.linear_solver, kind);
  solver->describe({dim, [&] { return step.node_coordinates(); }});
  std::unique_ptr<LinearSolver> general;  // made when a tangent is not positive definite
  Vector f_int;
  SparseMatrix K;
  const double floor = step.roundoff_force();
  for (int it = 0;; ++it) {
    auto t0 = Clock::now();
    step.internal_force(du, f_int);
    times.assembly += seconds_since(t0);
    Vector r = step.f_ext() - f_int;
    const double scale = std::max(step.f_ext().norm(), f_int.norm());
    for (int c : step.constrained()) r[c] = 0.0;
    double err = scale > 0.0 ? r.norm() / scale : 0.0;
    if (it == 0) {  // the prescribed increments are not applied yet: that is out of balance too
      double pending = 0.0;
      for (double v : step.increments()) pending = std::max(pending, std::abs(v));
      if (pending > 0.0) err = std::max(err, 1.0);
    }
    residuals.push_back(err);
    if (!std::isfinite(err)) throw StepFailure{"the out-of-balance force is not finite"};
    // Converged: relative to the forces, or (after the first iterate) at the round-off of
    // the internal force, which a tiny strain cannot beat.
    if (err < settings.tolerance || (it > 0 && r.norm() < floor)) {
      step.keep_converged_force(f_int);
      return du;
    }
    if (it == settings.max_iterations)
      throw StepFailure{fmt::format("no convergence in {} iterations (residual {:.3e})", it, err)};
    if (it >= 2 && err > 1e6 * std::max(residuals.front(), settings.tolerance))
      throw StepFailure{fmt::format("Newton diverges (residual {:.3e})", err)};
    t0 = Clock::now();
    step.stiffness(K);  // only when another iteration follows
    times.assembly += seconds_since(t0);
    DirichletElimination bc;
    bc.apply_to_matrix(K, step.constrained());
    bc.apply_to_rhs(r, it == 0 ? step.increments() : zeros);
    try {
      if (it == 0) {  // the pattern is fixed within the load step
        t0 = Clock::now();
        solver->analyze(K);
        times.analysis += seconds_since(t0);
      }
      try {
        t0 = Clock::now();
        solver->factorize(K);
        times.factor += seconds_since(t0);
        t0 = Clock::now();
        du += solver->solve(r);
        times.solve += seconds_since(t0);
      } catch (const SolverError&) {
        // Not positive definite at this iterate (a distorted trial state, or a genuine
        // instability): the symmetric indefinite system still has a Newton step.
        if (solver->general()) throw;
        t0 = Clock::now();
        if (!general) general = make_linear_solver(settings.linear_solver, MatrixKind::General);
        general->compute(K);
        du += general->solve(r);
        times.factor += seconds_since(t0);
        ++indefinite;
      }
      ++times.iterations;
    } catch (const SolverError& e) {
      throw StepFailure{e.what()};
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
  const double nominal = 1.0 / settings.load_steps;
  double lambda = start.load_factor, dlambda = start.next_increment > 0.0 ? start.next_increment : nominal;
  while (lambda < 1.0 - 1e-12) {
    dlambda = std::min(dlambda, 1.0 - lambda);
    StepInfo info;
    std::unique_ptr<LoadStep<dim>> step;  // kept for the grid fields the observer may ask for
    Vector du;
    const auto t0 = Clock::now();
    while (true) {
      info.residuals.clear();
      info.phases = PhaseTimes{};
      try {
        auto t0 = Clock::now();
        try {
          step = std::make_unique<LoadStep<dim>>(model, lambda + dlambda, dlambda);
        } catch (const std::out_of_range& e) {  // points left the grid: no cut can help
          throw SolverError(fmt::format("load step {} (load factor {:.6g}): {}", summary.steps + 1, lambda, e.what()));
        }
        info.phases.pattern = seconds_since(t0);
        info.dofs = step->dofs().num_dofs();
        info.nonzeros = step->pattern().nonZeros();
        du = newton(*step, settings, info.residuals, info.indefinite_solves, info.phases);
        t0 = Clock::now();
        step->commit(model, du);
        info.phases.update = seconds_since(t0);
        step->release_newton_data();
        break;
      } catch (const StepFailure& f) {
        if (info.cuts == settings.max_cuts)
          throw SolverError(
              fmt::format("load step {} failed from load factor {:.6g} with increment {:.3g} after {} cut(s): {}",
                          summary.steps + 1, lambda, dlambda, info.cuts, f.reason));
        dlambda *= 0.5;
        ++info.cuts;
        ++summary.cuts;
      }
    }
    lambda += dlambda;
    if (1.0 - lambda < 1e-12) lambda = 1.0;
    info.step = ++summary.steps;
    info.load_factor = lambda;
    info.increment = dlambda;
    info.seconds = seconds_since(t0);
    info.last = lambda >= 1.0;
    info.grid_displacement = [&] { return step->on_grid(du); };
    info.grid_reaction = [&] { return step->grid_reaction(); };
    info.grid_mass = [&] { return step->grid_mass(); };
    info.rigid_forces = [&] { return step->rigid_forces(); };
    summary.total_iterations += static_cast<int>(info.residuals.size()) - 1;
    if (info.cuts == 0) dlambda = std::min(2.0 * dlambda, nominal);  // grow back after a cut
    info.after = DriverState{lambda, dlambda, summary};
    const auto t_stages = Clock::now();
    for (PostStepStage<dim>* stage : stages) stage->after_step(model, info);
    info.stage_seconds = seconds_since(t_stages);
    if (observer) observer(model, info);
  }
  return summary;
}

template RunSummary run_quasi_static<1>(Model<1>&, const NewtonSettings&, const std::vector<PostStepStage<1>*>&,
                                        const StepObserver<1>&, const DriverState&);
template RunSummary run_quasi_static<2>(Model<2>&, const NewtonSettings&, const std::vector<PostStepStage<2>*>&,
                                        const StepObserver<2>&, const DriverState&);
template RunSummary run_quasi_static<3>(Model<3>&, const NewtonSettings&, const std::vector<PostStepStage<3>*>&,
                                        const StepObserver<3>&, const DriverState&);

}  // namespace gradmpm
