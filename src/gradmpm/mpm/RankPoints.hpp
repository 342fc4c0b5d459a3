#pragma once
// Which rank owns which points in a distributed run (docs/parallel.md).
//
// Each rank owns a box of the grid's cells (grid/RankBoxes.hpp: laid out as PETSc's DMDA
// lays out a structured grid) and the points whose current position lies in them; a
// cell's points (coupled by F-bar through their averaged volume change) share a rank. The
// boxes are cut once, from the points in the reference configuration (their original
// positions), at nearly equal counts per direction: every rank finds the same cut, a
// restarted run too, and points that move into another rank's cells change rank after
// the step (migrate_points, mpm/PointMigration.hpp). The balance drifts as the body
// deforms.
#include <algorithm>
#include <numeric>
#include <vector>

#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/grid/RankBoxes.hpp"
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

/// The grid's cells per direction, as RankBoxes takes them.
template <int dim>
std::vector<int> cells_of(const Grid<dim>& grid) {
  return std::vector<int>(grid.cells().begin(), grid.cells().end());
}

/// The cut (see the header) from every point's original position (RankBoxes::of_counts).
template <int dim>
RankBoxes rank_boxes(const Grid<dim>& grid, const std::vector<Vec<dim>>& original, int ranks) {
  std::vector<long long> per_key(grid.num_nodes(), 0);
  for (const int k : cell_corner_keys(grid, original)) ++per_key[k];
  return RankBoxes::of_counts(cells_of(grid), per_key, ranks);
}

/// The points of each of `ranks` ranks: the cells cut by the points at `original`
/// positions, the points taken by where they are now (`current`). A rank's points are
/// listed in increasing id.
template <int dim>
PointPartition points_of_ranks(const Grid<dim>& grid, const std::vector<Vec<dim>>& original,
                               const std::vector<Vec<dim>>& current, int ranks) {
  const int np = static_cast<int>(current.size());
  if (ranks == 1) return every_point(np);
  const RankBoxes boxes = rank_boxes(grid, original, ranks);
  const std::vector<int> key = cell_corner_keys(grid, current);
  std::vector<int> rank_of(np);
  PointPartition part;
  part.start.assign(ranks + 1, 0);
  for (int p = 0; p < np; ++p) {
    rank_of[p] = boxes.owner(key[p]);
    ++part.start[rank_of[p] + 1];
  }
  for (int r = 0; r < ranks; ++r) part.start[r + 1] += part.start[r];
  part.order.resize(np);
  std::vector<int> next(part.start.begin(), part.start.end() - 1);
  for (int p = 0; p < np; ++p) part.order[next[rank_of[p]]++] = p;
  return part;
}

/// The rank that owns each position x under the cut `boxes` (rank_boxes): its cell's owner.
template <int dim>
std::vector<int> owners(const Grid<dim>& grid, const RankBoxes& boxes, const std::vector<Vec<dim>>& x) {
  const std::vector<int> key = cell_corner_keys(grid, x);
  std::vector<int> rank(key.size());
  for (std::size_t p = 0; p < key.size(); ++p) rank[p] = boxes.owner(key[p]);
  return rank;
}

/// The rank each of the model's points belongs to now (its current cell under m.rank_boxes).
template <int dim>
std::vector<int> owners(const Model<dim>& m) {
  return owners(m.grid, m.rank_boxes, m.points.position);
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
