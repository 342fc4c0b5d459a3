#pragma once
// The points a rank works on in a load step of a distributed run (docs/parallel.md).
// Between load steps every rank holds every point (the outputs, checkpoints and the
// gradient step read them all); a load step works on this rank's points only: it is given
// a model of them (local_model), makes their stencils, Newton's point loops, its share of
// the tangent and the map of the converged increment to them, and at the end the ranks
// swap what the map wrote (share_committed), so every rank holds every point again.
//
// Which points: each rank owns a run of the grid's cells in their numbering (x fastest,
// so slabs across the grid's slowest axis, and part of a row where a cut falls inside
// one), and the points whose current position lies in them; a cell's points (coupled by
// F-bar through their averaged volume change) share a rank. The runs are cut once, from
// the points in the reference configuration (their original positions), at nearly equal
// counts: every rank finds the same cut, a restarted run too, and points that move into
// another rank's cells change rank with the next step, as in a partition of the grid into
// boxes (PETSc's DMDA). The balance of a run drifts as the body deforms.
#include <algorithm>
#include <vector>

#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/mpm/Model.hpp"
#include "gradmpm/mpm/PointPartition.hpp"

namespace gradmpm {

/// Each point's key: the grid node at the lower corner of the cell that holds x (node 0
/// for a point outside the grid: the load step's stencils report it).
template <int dim>
std::vector<int> cell_corner_keys(const Grid<dim>& grid, const std::vector<Vec<dim>>& x) {
  std::vector<int> key(x.size(), 0);
  for (std::size_t p = 0; p < x.size(); ++p)
    if (const auto c = grid.cell_of(x[p])) key[p] = grid.node_index(*c);
  return key;
}

/// The points of each of `ranks` ranks (see the header): the cells cut by the points at
/// `original` positions, the points taken by where they are now (`current`). A rank's
/// points are listed in increasing id.
template <int dim>
PointPartition points_of_ranks(const Grid<dim>& grid, const std::vector<Vec<dim>>& original,
                               const std::vector<Vec<dim>>& current, int ranks) {
  const int np = static_cast<int>(current.size());
  if (ranks == 1) return every_point(np);
  // The first key of each rank's cells.
  const std::vector<int> reference = cell_corner_keys(grid, original);
  const PointPartition cut = partition_points(reference, grid.num_nodes(), ranks);
  std::vector<int> first(ranks + 1, grid.num_nodes());
  first[0] = 0;
  for (int r = 1; r < ranks; ++r)
    if (cut.start[r] < np) first[r] = reference[cut.order[cut.start[r]]];
  const std::vector<int> key = cell_corner_keys(grid, current);
  std::vector<int> rank_of(np);
  PointPartition part;
  part.start.assign(ranks + 1, 0);
  for (int p = 0; p < np; ++p) {
    rank_of[p] = static_cast<int>(std::upper_bound(first.begin(), first.end() - 1, key[p]) - first.begin()) - 1;
    ++part.start[rank_of[p] + 1];
  }
  for (int r = 0; r < ranks; ++r) part.start[r + 1] += part.start[r];
  part.order.resize(np);
  std::vector<int> next(part.start.begin(), part.start.end() - 1);
  for (int p = 0; p < np; ++p) part.order[next[rank_of[p]]++] = p;
  return part;
}

/// The points of each rank of this run for a load step: points_of_ranks of the model's
/// points; every point on rank 0 in a serial run.
template <int dim>
PointPartition rank_points(const Model<dim>& m) {
  return points_of_ranks(m.grid, m.points.original_position, m.points.position, ranks::size());
}

/// The model with only the points `ids` (in that order), their state included; the grid,
/// the materials, the constraints and the rest as in `m`.
template <int dim>
Model<dim> local_model(Model<dim>& m, const std::vector<int>& ids) {
  MaterialPoints<dim> all = std::move(m.points);  // not copied with the rest
  Model<dim> local = m;
  m.points = std::move(all);
  local.points = m.points.subset(ids);
  return local;
}

/// The arrays of a point that a load step's map to the points writes (LoadStep::commit),
/// its state block apart: f(array of each of `pts`...) for each.
template <class F, class... Points>
void committed_arrays(F&& f, Points&... pts) {
  f(pts.position...);
  f(pts.F...);
  f(pts.volume...);
  f(pts.stress...);
  f(pts.fbar_jacobian...);
  f(pts.half_length...);
  f(pts.work...);
}

/// A distributed run's point array: each rank's values of its points (`mine`, in the
/// order of part.begin(rank) .. end(rank)) written at their ids into `all`, on every rank
/// (a collective call). `per_point` values of T (a double or a fixed-size Eigen type) per
/// point. A serial run's part is the identity.
template <class T>
void gather_points(const PointPartition& part, const T* mine, T* all, int per_point = 1) {
  static_assert(sizeof(T) % sizeof(double) == 0, "an array of doubles");
  const int width = static_cast<int>(sizeof(T) / sizeof(double)) * per_point, size = ranks::size();
  std::vector<int> counts(size);
  std::size_t total = 0;
  for (int r = 0; r < size; ++r) total += counts[r] = part.count(r) * width;
  std::vector<double> received(total);
  ranks::all_gather_rows(reinterpret_cast<const double*>(mine), counts, received.data());
  const double* v = received.data();
  for (const int p : part.order) {  // rank 0's points first, as received
    std::copy(v, v + width, reinterpret_cast<double*>(all + static_cast<std::size_t>(p) * per_point));
    v += width;
  }
}

/// After a load step of a distributed run: every rank's points as the step committed them
/// (`local`, the points part.begin(rank) .. end(rank), in that order) copied into `m` on
/// every rank (a collective call).
template <int dim>
void share_committed(const PointPartition& part, const MaterialPoints<dim>& local, MaterialPoints<dim>& m) {
  committed_arrays([&](const auto& mine, auto& all) { gather_points(part, mine.data(), all.data()); }, local, m);
  gather_points(part, local.state.data(), m.state.data(), m.state_stride);
}

}  // namespace gradmpm
