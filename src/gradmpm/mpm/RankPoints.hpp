#pragma once
// Which rank owns which points in a distributed run (docs/parallel.md).
//
// Each rank owns a run of the grid's cells in their numbering (x fastest, so slabs across
// the grid's slowest axis, and part of a row where a cut falls inside one), and the
// points whose current position lies in them; a cell's points (coupled by F-bar through
// their averaged volume change) share a rank. The runs are cut once, from the points in
// the reference configuration (their original positions), at nearly equal counts: every
// rank finds the same cut, a restarted run too, and points that move into another rank's
// cells change rank after the step (migrate_points, mpm/PointMigration.hpp), as in a
// partition of the grid into boxes (PETSc's DMDA). The balance of a run drifts as the
// body deforms.
#include <algorithm>
#include <numeric>
#include <vector>

#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/mpm/Model.hpp"
#include "gradmpm/mpm/PointMigration.hpp"
#include "gradmpm/mpm/PointPartition.hpp"

namespace gradmpm {

/// A point's key: the grid node at the lower corner of the cell that holds x (node 0 for
/// a point outside the grid: the load step's stencils report it).
template <int dim>
int cell_corner_key(const Grid<dim>& grid, const Vec<dim>& x) {
  const auto c = grid.cell_of(x);
  return c ? grid.node_index(*c) : 0;
}

/// Each point's key (cell_corner_key).
template <int dim>
std::vector<int> cell_corner_keys(const Grid<dim>& grid, const std::vector<Vec<dim>>& x) {
  std::vector<int> key(x.size());
  for (std::size_t p = 0; p < x.size(); ++p) key[p] = cell_corner_key(grid, x[p]);
  return key;
}

/// The cut (see the header) from the number of points of each key (cell corner node):
/// rank r owns the cells whose key is in [first[r], first[r + 1]); ranks + 1 entries. The
/// same cut as partition_points' (an even cut by count, moved on past the rest of its key).
inline std::vector<int> rank_cells_of_counts(const std::vector<long long>& per_key, int ranks) {
  const int nk = static_cast<int>(per_key.size());
  std::vector<long long> before(nk + 1, 0);  // points of keys < k
  for (int k = 0; k < nk; ++k) before[k + 1] = before[k] + per_key[k];
  const long long np = before[nk];
  std::vector<int> first(ranks + 1, nk);
  first[0] = 0;
  long long previous = 0;
  for (int r = 1; r < ranks; ++r) {
    long long cut = std::max(previous, np * r / ranks);
    // The key at position cut; a cut inside its key's points moves on past them.
    int k = static_cast<int>(std::upper_bound(before.begin(), before.end(), cut) - before.begin()) - 1;
    if (cut > 0 && cut < np && cut > before[k]) cut = before[k + 1];
    previous = cut;
    if (cut < np) first[r] = static_cast<int>(std::upper_bound(before.begin(), before.end(), cut) - before.begin()) - 1;
  }
  return first;
}

/// The cut from every point's original position (rank_cells_of_counts).
template <int dim>
std::vector<int> rank_cells(const Grid<dim>& grid, const std::vector<Vec<dim>>& original, int ranks) {
  std::vector<long long> per_key(grid.num_nodes(), 0);
  for (const int k : cell_corner_keys(grid, original)) ++per_key[k];
  return rank_cells_of_counts(per_key, ranks);
}

/// The rank that owns the cell of key `key` under the cut `first` (rank_cells).
inline int owner_of(const std::vector<int>& first, int key) {
  return static_cast<int>(std::upper_bound(first.begin(), first.end() - 1, key) - first.begin()) - 1;
}

/// The points of each of `ranks` ranks: the cells cut by the points at `original`
/// positions, the points taken by where they are now (`current`). A rank's points are
/// listed in increasing id.
template <int dim>
PointPartition points_of_ranks(const Grid<dim>& grid, const std::vector<Vec<dim>>& original,
                               const std::vector<Vec<dim>>& current, int ranks) {
  const int np = static_cast<int>(current.size());
  if (ranks == 1) return every_point(np);
  const std::vector<int> first = rank_cells(grid, original, ranks);
  const std::vector<int> key = cell_corner_keys(grid, current);
  std::vector<int> rank_of(np);
  PointPartition part;
  part.start.assign(ranks + 1, 0);
  for (int p = 0; p < np; ++p) {
    rank_of[p] = owner_of(first, key[p]);
    ++part.start[rank_of[p] + 1];
  }
  for (int r = 0; r < ranks; ++r) part.start[r + 1] += part.start[r];
  part.order.resize(np);
  std::vector<int> next(part.start.begin(), part.start.end() - 1);
  for (int p = 0; p < np; ++p) part.order[next[rank_of[p]]++] = p;
  return part;
}

/// The rank that owns each position x under the cut `first` (rank_cells): its cell's owner.
template <int dim>
std::vector<int> owners(const Grid<dim>& grid, const std::vector<int>& first, const std::vector<Vec<dim>>& x) {
  const std::vector<int> key = cell_corner_keys(grid, x);
  std::vector<int> rank(key.size());
  for (std::size_t p = 0; p < key.size(); ++p) rank[p] = owner_of(first, key[p]);
  return rank;
}

/// The rank each of the model's points belongs to now (its current cell under m.rank_cells).
template <int dim>
std::vector<int> owners(const Model<dim>& m) {
  return owners(m.grid, m.rank_cells, m.points.position);
}

/// Applies a migration to the model's points: every array, the state block, the ids.
template <int dim>
void migrate_points(Model<dim>& m, const PointMigration& migration) {
  if (m.point_ids.empty()) {  // every point, in id order
    m.point_ids.resize(m.points.size());
    std::iota(m.point_ids.begin(), m.point_ids.end(), 0);
  }
  migration.apply(m.point_ids);
  m.points.for_each_array([&](const char*, auto& array) { migration.apply(array); });
  if (m.points.state_stride > 0) migration.apply(m.points.state, m.points.state_stride);
}

}  // namespace gradmpm
