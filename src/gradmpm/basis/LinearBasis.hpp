#pragma once
// Standard MPM basis: the (multi)linear hat functions of the background grid cell
// that contains the point (tensor products of N0 = 1 - xi, N1 = xi). This is also
// the linear finite element, which is why FEM is the special case of MPM whose
// points sit at Gauss positions and never move.
#include "gradmpm/basis/Stencil.hpp"
#include "gradmpm/grid/Grid.hpp"

namespace gradmpm {

template <int dim>
struct LinearBasis {
  /// Fills `s` with the 2^dim nodes of the cell holding x. Returns false when x is
  /// outside the grid (the stencil is then empty).
  static bool evaluate(const Grid<dim>& grid, const Vec<dim>& x, Stencil<dim>& s) {
    return evaluate(grid, x, Vec<dim>::Zero(), s);
  }
  /// Same signature as GimpBasis; the point's domain is ignored.
  static bool evaluate(const Grid<dim>& grid, const Vec<dim>& x, const Vec<dim>& /*lp*/, Stencil<dim>& s) {
    const auto cell = grid.cell_of(x);
    s.count = 0;
    if (!cell) return false;
    double n1[dim][2], d1[dim][2];  // 1D values and derivatives per direction
    for (int d = 0; d < dim; ++d) {
      const double h = grid.cell_size()[d];
      const double xi = (x[d] - grid.origin()[d]) / h - (*cell)[d];
      n1[d][0] = 1.0 - xi;
      n1[d][1] = xi;
      d1[d][0] = -1.0 / h;
      d1[d][1] = 1.0 / h;
    }
    constexpr int corners = 1 << dim;
    for (int c = 0; c < corners; ++c) {
      typename Grid<dim>::Index ijk;
      double N = 1.0;
      Vec<dim> dN = Vec<dim>::Ones();
      for (int d = 0; d < dim; ++d) {
        const int bit = (c >> d) & 1;
        ijk[d] = (*cell)[d] + bit;
        N *= n1[d][bit];
        for (int e = 0; e < dim; ++e) dN[e] *= (e == d) ? d1[d][bit] : n1[d][bit];
      }
      s.node[s.count] = grid.node_index(ijk);
      s.N[s.count] = N;
      s.dN[s.count] = dN;
      ++s.count;
    }
    return true;
  }
};

}  // namespace gradmpm
