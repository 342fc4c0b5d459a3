#pragma once
// The implicit quasi-static MPM (paper, section 1; AMPLE's algorithm):
//
//   for each load step                                   (load factor lambda_n -> lambda_n+1)
//     shape functions of the points at x_n; active nodes; sparsity pattern (once per step)
//     external force f_ext = sum_p N_i (m_p g + f_p) lambda      (eq. 1)
//     Newton-Raphson on the grid displacement increment du:
//       point loop: dF = I + grad_n du, material update, f_int and tangent K (point sums)
//       r = f_ext - f_int; stop when |r_free| / max(|f_ext|, |f_int|) < tol
//       K d = r (CHOLMOD, symbolic analysis reused), du += d
//     map du to the points (eq. 2), update x, F, volume, stress, domains; reset the grid
//     (on several MPI ranks: points that moved into another rank's cells go to it)
//     post-step stages (the gradient step, ...), then the observer (outputs)
//
// A failing step (no convergence in max_iterations, divergence, a singular tangent) is
// retried with half the increment, up to max_cuts times; then SolverError is thrown and
// the model keeps the state of the last converged step.
#include <functional>
#include <string>
#include <vector>

#include "gradmpm/io/Archive.hpp"
#include "gradmpm/mpm/Model.hpp"
#include "gradmpm/mpm/PointMigration.hpp"

namespace gradmpm {

template <int dim>
using StepObserver = std::function<void(const Model<dim>&, const StepInfo&)>;

/// Work the driver does after every converged load step, in order, before the observer:
/// the gradient step (gradient/MpmGradient.hpp) is one; the plastic regularisation will
/// be another. Recipe "add a post-step stage" (docs/architecture.md): derive, implement
/// name() and after_step(), pass it to run_quasi_static; tests/test_mpm_newton.cpp does.
template <int dim>
class PostStepStage {
 public:
  virtual ~PostStepStage() = default;
  virtual std::string name() const = 0;
  /// After the points hold the converged state of step `info.step`.
  virtual void after_step(Model<dim>& model, const StepInfo& info) = 0;
  /// A stage that carries state from step to step puts it in a checkpoint
  /// (app/Checkpoint.hpp) and takes it back on restart, under names starting "name()/":
  /// arrays with one entry (of a fixed number of values) per point, in the points' order,
  /// so that a restart on another number of ranks splits them with the points. restore()
  /// reads how many points this rank now has from "points/count".
  virtual void save(Archive&) const {}
  virtual void restore(const Archive&) {}
  /// A distributed run's points changed ranks: a stage that carries arrays with one entry
  /// per point moves each of them with `migration` (PointMigration::apply; a collective call).
  virtual void migrate(const PointMigration&) {}
};

/// A distributed run's point ownership (mpm/RankPoints.hpp, docs/parallel.md); in a
/// serial run each is a no-op. Collective calls, the stages' per-point arrays moved with
/// the points.
/// The cut of the grid made from the model's points (every rank holds every point, just
/// restored from a checkpoint, or a model built in code), and each rank keeps the points in
/// its cells. Nothing is done when the points are owned already (Model::rank_boxes set:
/// read_mpm_case made this rank's points only).
template <int dim>
void own_rank_points(Model<dim>& model, const std::vector<PostStepStage<dim>*>& stages);
/// Points that are in another rank's cells go to it; returns how many this rank sent.
template <int dim>
int migrate_to_owners(Model<dim>& model, const std::vector<PostStepStage<dim>*>& stages);
/// Every point to rank 0, in id order (output.check's verification); migrate_to_owners
/// gives them back.
template <int dim>
void collect_on_root(Model<dim>& model, const std::vector<PostStepStage<dim>*>& stages);
/// The points in id order across the ranks: rank r takes the r-th of P even runs of ids,
/// so that the ranks' rows one after another are every point in id order (the final CSV
/// files, written by each rank at its place); migrate_to_owners gives them back.
template <int dim>
void arrange_by_id(Model<dim>& model, const std::vector<PostStepStage<dim>*>& stages);

/// Runs the analysis from load factor 0 (or from `start`, a restart) to 1 in
/// settings.load_steps nominal steps.
template <int dim>
RunSummary run_quasi_static(Model<dim>& model, const NewtonSettings& settings,
                            const std::vector<PostStepStage<dim>*>& stages, const StepObserver<dim>& observer = {},
                            const DriverState& start = {});

/// The same without post-step stages.
template <int dim>
RunSummary run_quasi_static(Model<dim>& model, const NewtonSettings& settings, const StepObserver<dim>& observer = {}) {
  return run_quasi_static<dim>(model, settings, {}, observer);
}

}  // namespace gradmpm
