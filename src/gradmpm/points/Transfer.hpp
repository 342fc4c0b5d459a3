#pragma once
// Point <-> grid transfers of the MPM. (Interpolation of a nodal field to the points,
// eq. (2) of the paper, is Assembler::interpolate.)
//  - points_to_nodes: volume-weighted recovery of a point field at the nodes,
//      q_i = sum_p N_i(x_p) V_p q_p / sum_p N_i(x_p) V_p,
//    the mapping of eq. (1) normalised by the nodal "volume" (a lumped L2 projection).
//    It reproduces constant fields exactly and, on a uniform 1D mesh with fields that
//    are constant per element, gives the average of the two neighbouring elements.
#include <algorithm>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "gradmpm/basis/BasisKind.hpp"
#include "gradmpm/basis/GimpBasis.hpp"
#include "gradmpm/basis/LinearBasis.hpp"
#include "gradmpm/basis/Stencil.hpp"
#include "gradmpm/core/Parallel.hpp"
#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/grid/Grid.hpp"
#include "gradmpm/grid/NodeSums.hpp"
#include "gradmpm/points/MaterialPoints.hpp"

namespace gradmpm {

/// Shape functions of every point, evaluated once per load step.
template <int dim>
using PointStencils = std::vector<Stencil<dim>>;

/// Evaluates `Basis` at every point. Throws std::out_of_range listing the ids of
/// points outside the grid (for GIMP: whose domain leaves the grid) and, for GIMP, of
/// points whose domain has grown wider than a cell (cpGIMP under large stretch).
/// `ids`: where `points` are a distributed run's rank's points (mpm/RankPoints.hpp), their
/// ids in the whole body; then the ranks' failures are gathered (a collective call), so
/// every rank throws the same message, the one a serial run gives.
template <int dim, class Basis>
PointStencils<dim> evaluate_stencils(const Grid<dim>& grid, const MaterialPoints<dim>& points,
                                     const std::vector<int>* ids = nullptr) {
  const int np = points.size();
  PointStencils<dim> st(np);
  std::vector<char> ok(np);
#pragma omp parallel for schedule(static) if (use_threads(np))
  for (int p = 0; p < np; ++p) ok[p] = Basis::evaluate(grid, points.position[p], points.half_length[p], st[p]);
  std::vector<int> outside, too_wide;
  for (int p = 0; p < np; ++p) {
    if (ok[p]) continue;
    bool wide = false;
    if constexpr (std::is_same_v<Basis, GimpBasis<dim>>)
      for (int d = 0; d < dim; ++d) wide = wide || points.half_length[p][d] > 0.5 * grid.cell_size()[d];
    (wide ? too_wide : outside).push_back(ids ? (*ids)[p] : p);
  }
  if (ids) {
    outside = ranks::all_gather(outside);
    too_wide = ranks::all_gather(too_wide);
    std::sort(outside.begin(), outside.end());
    std::sort(too_wide.begin(), too_wide.end());
  }
  auto listed = [](const std::vector<int>& v) {
    std::string text;
    for (std::size_t k = 0; k < v.size() && k < 20; ++k) text += (k ? ", " : "") + std::to_string(v[k]);
    return text + (v.size() > 20 ? ", ..." : "");
  };
  std::string message;
  if (!outside.empty())
    message = std::to_string(outside.size()) + " material point(s) outside the grid (ids): " + listed(outside);
  if (!too_wide.empty())
    message += (message.empty() ? "" : "; ") + std::to_string(too_wide.size()) +
               " material point(s) whose GIMP domain is wider than a grid cell (ids): " + listed(too_wide) +
               " (cpGIMP domains stretch with the body: use more points per cell or uGIMP)";
  if (!message.empty()) throw std::out_of_range(message);
  return st;
}

/// Runtime choice of basis (uGIMP and cpGIMP differ only in how l_p evolves).
template <int dim>
PointStencils<dim> evaluate_stencils(const Grid<dim>& grid, const MaterialPoints<dim>& points, BasisKind kind,
                                     const std::vector<int>* ids = nullptr) {
  if (kind == BasisKind::MPM) return evaluate_stencils<dim, LinearBasis<dim>>(grid, points, ids);
  return evaluate_stencils<dim, GimpBasis<dim>>(grid, points, ids);
}

/// Removes from every stencil the nodes for which `drop(node)` holds, keeping the order of
/// the others (their shape functions are left out of the partition of unity).
template <int dim, class Drop>
void drop_nodes(PointStencils<dim>& st, Drop&& drop) {
  for (auto& s : st) {
    int k = 0;
    for (int a = 0; a < s.count; ++a)
      if (!drop(s.node[a])) {
        s.node[k] = s.node[a];
        s.N[k] = s.N[a];
        s.dN[k] = s.dN[a];
        ++k;
      }
    s.count = k;
  }
}

/// Removes from every stencil the grid nodes whose support, sum_p N_i(x_p) v_p, is below
/// `relative` times a cell's volume: a node that points reach only by a sliver (a surface
/// point that has moved a hair into the next cell, a GIMP domain overlapping a node's
/// support by round-off) has an equation of near-zero stiffness, and Newton's correction
/// there is unbounded (the footing of docs/plasticity.md: singular values 1e-16 of the
/// largest). Returns how many nodes were dropped; their shape functions are left out,
/// an error of the order of `relative` in the partition of unity. `boxes`: a
/// distributed run's partition (the points being its rank's): the supports at this
/// rank's stencils' nodes are summed over the ranks at their owners (sum_at_owners), and
/// the count returned is of the nodes this rank's stencils reach.
template <int dim>
int drop_weak_nodes(PointStencils<dim>& st, const MaterialPoints<dim>& points, int num_nodes, double cell_volume,
                    double relative, const RankBoxes* boxes = nullptr) {
  Paged<double> support(num_nodes, 0.0);  // (pages near the stencils' nodes only)
  for (std::size_t p = 0; p < st.size(); ++p)
    for (int a = 0; a < st[p].count; ++a) support.at(st[p].node[a]) += st[p].N[a] * points.volume[p];
  const std::vector<int> touched = stencil_nodes(st);
  if (boxes) sum_at_owners(*boxes, support, touched);
  const double floor = relative * cell_volume;
  int dropped = 0;  // (of the stencils' nodes: the ones a drop can change)
  for (const int n : touched) dropped += support[n] > 0.0 && support[n] < floor;
  if (dropped == 0) return 0;
  drop_nodes(st, [&](int node) { return support[node] < floor; });
  return dropped;
}

/// Volume-weighted recovery of a scalar point field at the nodes (see header).
/// Nodes that no point touches get 0.
template <int dim>
Vector points_to_nodes(const PointStencils<dim>& st, const MaterialPoints<dim>& points, const std::vector<double>& q,
                       int num_nodes) {
  Vector num = Vector::Zero(num_nodes), den = Vector::Zero(num_nodes);
  for (std::size_t p = 0; p < st.size(); ++p) {
    for (int a = 0; a < st[p].count; ++a) {
      const double w = st[p].N[a] * points.volume[p];
      num[st[p].node[a]] += w * q[p];
      den[st[p].node[a]] += w;
    }
  }
  for (int i = 0; i < num_nodes; ++i) num[i] = den[i] > 0.0 ? num[i] / den[i] : 0.0;
  return num;
}

/// Nodal masses sum_p N_i m_p at every grid node.
template <int dim>
Vector nodal_mass(const PointStencils<dim>& st, const MaterialPoints<dim>& points, int num_nodes) {
  Vector mass = Vector::Zero(num_nodes);
  for (std::size_t p = 0; p < st.size(); ++p)
    for (int a = 0; a < st[p].count; ++a) mass[st[p].node[a]] += st[p].N[a] * points.mass[p];
  return mass;
}

/// Point p's share of the external force, eq. (1): f_i += N_i(x_p) (m_p g g_factor +
/// f_p lambda), dim components per active node in the equation numbering of `dofs`;
/// g_factor is lambda, or 1 where gravity is a dead load (an initial stress in balance
/// with it). Summed over the points by the caller (LoadStep: by the assembler's strips).
template <int dim, class DofNumbering>
void add_external_force(const PointStencils<dim>& st, const MaterialPoints<dim>& points, const Vec<dim>& gravity,
                        double g_factor, double lambda, const DofNumbering& dofs, int p, Vector& f_ext) {
  const Vec<dim> f = g_factor == lambda ? Vec<dim>((points.mass[p] * gravity + points.force[p]) * lambda)
                                        : Vec<dim>(points.mass[p] * gravity * g_factor + points.force[p] * lambda);
  for (int a = 0; a < st[p].count; ++a)
    for (int i = 0; i < dim; ++i) f_ext[dofs.dof(st[p].node[a], i)] += st[p].N[a] * f[i];
}

}  // namespace gradmpm
