#pragma once
// GIMP basis (Bardenhagen & Kober 2004): the linear hat functions averaged over the
// point's domain [x_p - l_p, x_p + l_p] per direction, which makes the weights and their
// gradients continuous as a point crosses a cell boundary (no stress spikes). uGIMP keeps
// l_p at its initial value; cpGIMP stretches it with the deformation (MaterialPoints).
// Per direction, with d = x_p - x_i and cell size h (valid for l_p < h/2):
//   S = (h + l_p + d)^2 / (4 h l_p)          -h - l_p < d <= -h + l_p
//     = 1 + d/h                              -h + l_p < d <= -l_p
//     = 1 - (d^2 + l_p^2) / (2 h l_p)          -l_p < d <= l_p
//     = 1 - d/h                                 l_p < d <= h - l_p
//     = (h + l_p - d)^2 / (4 h l_p)           h - l_p < d <= h + l_p
#include <cmath>

#include "gradmpm/basis/Stencil.hpp"
#include "gradmpm/grid/Grid.hpp"

namespace gradmpm {

/// One-dimensional GIMP weight and derivative; returns false outside the support. An
/// overlap below 1e-9 h counts as none: a domain that touches the edge of a node's
/// support to round-off would otherwise bring in a node with N ~ 1e-16 and no stiffness.
inline bool gimp_1d(double d, double h, double lp, double& S, double& dS) {
  const double a = std::abs(d);
  if (a >= h + lp - 1e-9 * h) return false;
  const double sgn = d < 0 ? -1.0 : 1.0;
  if (a <= lp) {
    S = 1.0 - (d * d + lp * lp) / (2.0 * h * lp);
    dS = -d / (h * lp);
  } else if (a <= h - lp) {
    S = 1.0 - a / h;
    dS = -sgn / h;
  } else {
    S = (h + lp - a) * (h + lp - a) / (4.0 * h * lp);
    dS = -sgn * (h + lp - a) / (2.0 * h * lp);
  }
  return S > 0.0 || dS != 0.0;
}

template <int dim>
struct GimpBasis {
  /// Fills `s` for a point at x with domain half-lengths lp. Returns false if the domain
  /// leaves the grid (the weights would no longer sum to one) or lp is not in (0, h/2].
  static bool evaluate(const Grid<dim>& grid, const Vec<dim>& x, const Vec<dim>& lp, Stencil<dim>& s) {
    s.count = 0;
    int nodes[dim][3] = {}, n_dir[dim] = {};
    double S[dim][3] = {}, dS[dim][3] = {};
    for (int d = 0; d < dim; ++d) {
      const double h = grid.cell_size()[d], o = grid.origin()[d];
      if (!(lp[d] > 0.0) || lp[d] > 0.5 * h) return false;
      if (!(x[d] - lp[d] >= o - 1e-12 * h) || x[d] + lp[d] > o + grid.cells()[d] * h + 1e-12 * h) return false;
      n_dir[d] = 0;
      const int first = static_cast<int>(std::ceil((x[d] - lp[d] - h - o) / h));
      for (int i = std::max(first, 0); i <= grid.cells()[d] && i * h + o < x[d] + lp[d] + h; ++i) {
        double w, dw;
        if (!gimp_1d(x[d] - (o + i * h), h, lp[d], w, dw)) continue;
        if (n_dir[d] == 3) return false;  // cannot happen for lp <= h/2
        nodes[d][n_dir[d]] = i;
        S[d][n_dir[d]] = w;
        dS[d][n_dir[d]] = dw;
        ++n_dir[d];
      }
      if (n_dir[d] == 0) return false;
    }
    int idx[dim] = {};
    while (true) {
      typename Grid<dim>::Index ijk;
      double N = 1.0;
      Vec<dim> dN = Vec<dim>::Ones();
      for (int d = 0; d < dim; ++d) {
        ijk[d] = nodes[d][idx[d]];
        N *= S[d][idx[d]];
        for (int e = 0; e < dim; ++e) dN[e] *= (e == d) ? dS[d][idx[d]] : S[d][idx[d]];
      }
      s.node[s.count] = grid.node_index(ijk);
      s.N[s.count] = N;
      s.dN[s.count] = dN;
      ++s.count;
      int d = 0;
      while (d < dim && ++idx[d] == n_dir[d]) idx[d++] = 0;
      if (d == dim) break;
    }
    return true;
  }
};

}  // namespace gradmpm
