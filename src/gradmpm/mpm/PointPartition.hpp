#pragma once
// Which rank does which points' work in a load step's Newton loops (a distributed run,
// core/Ranks.hpp). Each point has a key, a grid node: by default the lowest node of its
// stencil; with F-bar the lowest node of its cell's points' stencils, so that a cell's
// points, coupled through their averaged volume change, share one rank. Nodes are numbered
// x fastest, so ordering the points by key orders them by the grid's slowest axis first;
// they are cut into runs of nearly equal count, one per rank, at key boundaries only:
// slabs of the body across its longest direction in the usual layout, balanced by points
// rather than by cells. Every rank computes the same partition from the same stencils. It
// is made again every load step, so points that move into another slab change rank with
// the step.
#include <algorithm>
#include <vector>

#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/points/Transfer.hpp"

namespace gradmpm {

struct PointPartition {
  std::vector<int> order;  ///< every point, rank 0's first
  std::vector<int> start;  ///< rank r's points: order[start[r] .. start[r + 1])

  int count(int r) const { return start[r + 1] - start[r]; }
  const int* begin(int r) const { return order.data() + start[r]; }
  const int* end(int r) const { return order.data() + start[r + 1]; }
};

/// A serial run's partition: every point, in index order, on rank 0.
inline PointPartition every_point(int np) {
  PointPartition part;
  part.order.resize(np);
  for (int p = 0; p < np; ++p) part.order[p] = p;
  part.start = {0, np};
  return part;
}

/// The default key of every point: the lowest node of its stencil.
template <int dim>
std::vector<int> lowest_stencil_nodes(const PointStencils<dim>& st, int num_nodes) {
  std::vector<int> key(st.size());
  for (std::size_t p = 0; p < st.size(); ++p) {
    int lowest = num_nodes - 1;
    for (int a = 0; a < st[p].count; ++a) lowest = std::min(lowest, st[p].node[a]);
    key[p] = lowest;
  }
  return key;
}

/// The points cut into `ranks` runs by `key` (one grid node per point, < num_nodes); the
/// points of one key always share a rank.
inline PointPartition partition_points(const std::vector<int>& key, int num_nodes, int ranks) {
  const int np = static_cast<int>(key.size());
  if (ranks == 1) return every_point(np);
  PointPartition part;
  part.order.resize(np);
  // A counting sort by key; points of one key keep index order.
  std::vector<int> first(num_nodes + 1, 0);
  for (int p = 0; p < np; ++p) ++first[key[p] + 1];
  for (int n = 0; n < num_nodes; ++n) first[n + 1] += first[n];
  for (int p = 0; p < np; ++p) part.order[first[key[p]]++] = p;
  part.start.assign(ranks + 1, np);
  part.start[0] = 0;
  for (int r = 1; r < ranks; ++r) {  // the even cut, moved on past the rest of its key
    int cut = std::max(part.start[r - 1], static_cast<int>(static_cast<long long>(np) * r / ranks));
    while (cut > 0 && cut < np && key[part.order[cut]] == key[part.order[cut - 1]]) ++cut;
    part.start[r] = cut;
  }
  return part;
}

/// The points of each rank for an operator assembled from the stencils `st` (the Helmholtz
/// systems): by the lowest node of their stencil; every point on rank 0 in a serial run.
template <int dim>
PointPartition stencil_partition(const PointStencils<dim>& st, int num_nodes) {
  if (!ranks::distributed()) return every_point(static_cast<int>(st.size()));
  return partition_points(lowest_stencil_nodes(st, num_nodes), num_nodes, ranks::size());
}

/// A distributed run's failed point: the lowest `point` over the ranks (`none` where no
/// rank has one) and the `value` its owner found for it, on every rank.
inline void lowest_over_ranks(int& point, double& value, int none) {
  const int lowest = ranks::min(point);
  double v = lowest == point ? value : 0.0;  // points are unique to ranks: one owner adds it
  if (lowest < none) ranks::sum(&v, 1);
  point = lowest;
  value = v;
}

/// After a converged iterate of a distributed run: every rank's points' stresses (9
/// values at stress_of(p), a 3x3 matrix) and histories (`stride` values per point in
/// `state`) copied to every other rank, which computed only its own.
template <class StressOf>
void share_point_results(const PointPartition& part, int stride, StressOf&& stress_of, double* state) {
  const int me = ranks::rank(), size = ranks::size(), width = 9 + stride;
  std::vector<double> mine;
  mine.reserve(static_cast<std::size_t>(part.count(me)) * width);
  for (const int* p = part.begin(me); p != part.end(me); ++p) {
    const double* s = stress_of(*p);
    mine.insert(mine.end(), s, s + 9);
    mine.insert(mine.end(), state + static_cast<std::size_t>(*p) * stride,
                state + static_cast<std::size_t>(*p + 1) * stride);
  }
  std::vector<int> counts(size);
  std::size_t total = 0;
  for (int r = 0; r < size; ++r) total += counts[r] = part.count(r) * width;
  std::vector<double> all(total);
  ranks::all_gather_rows(mine.data(), counts, all.data());
  const double* v = all.data();
  for (int r = 0; r < size; ++r)
    for (const int* p = part.begin(r); p != part.end(r); ++p, v += width) {
      if (r == me) continue;
      std::copy(v, v + 9, stress_of(*p));
      std::copy(v + 9, v + width, state + static_cast<std::size_t>(*p) * stride);
    }
}

}  // namespace gradmpm
