#pragma once
// The displacement increment of a load step seen from one point: its gradient in the
// configuration at the start of the step (what the material update and F-bar take) and,
// on commit, the point's displacement (eq. 2).
#include "gradmpm/basis/Stencil.hpp"
#include "gradmpm/core/Types.hpp"
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

}  // namespace gradmpm::detail
