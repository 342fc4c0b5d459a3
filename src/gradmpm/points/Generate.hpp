#pragma once
// Populating cells with material points. With Gauss-Legendre positions and weights
// the points are exactly the integration points of the finite element method.
#include <array>
#include <functional>
#include <stdexcept>

#include "gradmpm/grid/Grid.hpp"
#include "gradmpm/points/MaterialPoints.hpp"

namespace gradmpm {

/// Gauss-Legendre rule on [0, 1] with n = 1..4 points.
struct GaussRule01 {
  std::array<double, 4> xi{};
  std::array<double, 4> w{};
  int n = 0;
  explicit GaussRule01(int points);
};

/// Adds n^dim Gauss points to every cell c with first[d] <= c[d] < last[d].
/// `material_at(x)` gives the material index of a point at x.
template <int dim>
void add_gauss_points(const Grid<dim>& grid, const typename Grid<dim>::Index& first,
                      const typename Grid<dim>::Index& last, int n,
                      const std::function<int(const Vec<dim>&)>& material_at, MaterialPoints<dim>& points) {
  const GaussRule01 rule(n);
  const Vec<dim>& h = grid.cell_size();
  int per_cell = 1;
  for (int d = 0; d < dim; ++d) per_cell *= n;

  std::array<int, dim> c = first;
  for (int d = 0; d < dim; ++d)
    if (first[d] >= last[d]) return;
  while (true) {
    for (int q = 0; q < per_cell; ++q) {
      Vec<dim> x, lp;
      double w = 1.0;
      int r = q;
      for (int d = 0; d < dim; ++d) {
        const int iq = r % n;
        r /= n;
        x[d] = grid.origin()[d] + (c[d] + rule.xi[iq]) * h[d];
        w *= rule.w[iq] * h[d];
        lp[d] = 0.5 * rule.w[iq] * h[d];  // the point's share of the cell
      }
      points.add(x, w, material_at(x), lp);
    }
    int d = 0;  // odometer over the cell box
    while (d < dim && ++c[d] == last[d]) {
      c[d] = first[d];
      ++d;
    }
    if (d == dim) break;
  }
}

/// Calls f(x) for each of n^dim equally spaced points per cell (the usual MPM filling: cell
/// split into n^dim sub-cells, one point at each centre) of every cell c with first <= c <
/// last whose point satisfies `inside(x)`, in the order add_regular_points adds them.
template <int dim, class F>
void for_each_regular_point(const Grid<dim>& grid, const typename Grid<dim>::Index& first,
                            const typename Grid<dim>::Index& last, int n,
                            const std::function<bool(const Vec<dim>&)>& inside, F&& f) {
  const Vec<dim>& h = grid.cell_size();
  int per_cell = 1;
  for (int d = 0; d < dim; ++d) per_cell *= n;
  std::array<int, dim> c = first;
  for (int d = 0; d < dim; ++d)
    if (first[d] >= last[d]) return;
  while (true) {
    for (int q = 0; q < per_cell; ++q) {
      Vec<dim> x;
      int r = q;
      for (int d = 0; d < dim; ++d) {
        x[d] = grid.origin()[d] + (c[d] + (r % n + 0.5) / n) * h[d];
        r /= n;
      }
      if (inside(x)) f(x);
    }
    int d = 0;
    while (d < dim && ++c[d] == last[d]) {
      c[d] = first[d];
      ++d;
    }
    if (d == dim) break;
  }
}

/// Adds the points of for_each_regular_point that `keep(x)` accepts (every one by
/// default). Volume = sub-cell volume, domain = the sub-cell. Returns the points visited
/// (kept or not).
template <int dim>
int add_regular_points(const Grid<dim>& grid, const typename Grid<dim>::Index& first,
                       const typename Grid<dim>::Index& last, int n, const std::function<bool(const Vec<dim>&)>& inside,
                       int material, double density, MaterialPoints<dim>& points,
                       const std::function<bool(const Vec<dim>&)>& keep = {}) {
  const Vec<dim> lp = grid.cell_size() / (2.0 * n);
  const double v = (grid.cell_size() / n).prod();
  int visited = 0;
  for_each_regular_point<dim>(grid, first, last, n, inside, [&](const Vec<dim>& x) {
    ++visited;
    if (!keep || keep(x)) points.add(x, v, material, lp, density * v);
  });
  return visited;
}

}  // namespace gradmpm
