#pragma once
// The displacement increment of a load step seen from one point: its gradient in the
// configuration at the start of the step (what the material update and F-bar take) and,
// on commit, the point's displacement (eq. 2) and the work of its stress.
#include "gradmpm/basis/Stencil.hpp"
#include "gradmpm/core/Types.hpp"
#include "gradmpm/points/MaterialPoints.hpp"
#include "gradmpm/solver/DofMap.hpp"

namespace gradmpm::detail {

/// grad_n du = sum_a du_a (x) dN_a at one point (embedded in 3x3), and optionally the
/// point's displacement sum_a N_a du_a (eq. 2).
template <int dim>
Mat3 increment_gradient(const Stencil<dim>& s, const DofMap& dofs, const Vector& du, Vec<dim>* dx = nullptr) {
  Mat3 g = Mat3::Zero();
  if (dx) dx->setZero();
  for (int a = 0; a < s.count; ++a)
    for (int i = 0; i < dim; ++i) {
      const double u = du[dofs.dof(s.node[a], i)];
      if (dx) (*dx)[i] += s.N[a] * u;
      for (int j = 0; j < dim; ++j) g(i, j) += u * s.dN[a][j];
    }
  return g;
}

/// The work of point p's stress over a load step (MaterialPoints::work), by the trapezoid
/// rule on the increment its material sees, dF = I + g (with F-bar, dFbar):
/// 1/2 (W_n : g + W_n+1 : g dF^-1), W the stress times its volume: V_p tau (finite strain,
/// tau : d per reference volume, d = g dF^-1 at the step's end, g at its start; tau_n is
/// J_n sigma_n, Jbar_n sigma_n with F-bar) or v_n sigma (small strain, g at both ends).
/// Before the step moves the point; tau_end is the converged iterate's stress.
template <int dim>
double step_work(const MaterialPoints<dim>& pts, int p, const Mat3& dF, const Mat3& tau_end, bool finite_strain,
                 bool fbar) {
  const Mat3 g = dF - Mat3::Identity();
  const double w = finite_strain ? pts.original_volume[p] : pts.volume[p];
  const double J_n = fbar ? pts.fbar_jacobian[p] : pts.volume[p] / pts.original_volume[p];
  const double w_n = finite_strain ? w * J_n : w;
  const Mat3 g_end = finite_strain ? Mat3(g * (Mat3::Identity() + g).inverse()) : g;
  return 0.5 * ((w_n * pts.stress[p]).cwiseProduct(g).sum() + (w * tau_end).cwiseProduct(g_end).sum());
}

}  // namespace gradmpm::detail
