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
//
// A failing step (no convergence in max_iterations, divergence, a singular tangent) is
// retried with half the increment, up to max_cuts times; then SolverError is thrown and
// the model keeps the state of the last converged step.
#include <functional>

#include "gradmpm/mpm/Model.hpp"

namespace gradmpm {

template <int dim>
using StepObserver = std::function<void(const Model<dim>&, const StepInfo&)>;

struct RunSummary {
  int steps = 0;
  int total_iterations = 0;
  int cuts = 0;
};

/// Runs the analysis from load factor 0 to 1 in settings.load_steps nominal steps.
template <int dim>
RunSummary run_quasi_static(Model<dim>& model, const NewtonSettings& settings,
                            const StepObserver<dim>& observer = {});

}  // namespace gradmpm
