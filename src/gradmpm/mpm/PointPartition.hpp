#pragma once
// Which rank does which points' work in a load step's Newton loops (a distributed run,
// core/Ranks.hpp). The points are ordered by the lowest grid node of their stencil
// (nodes are numbered x fastest, so this orders them by the grid's slowest axis first)
// and cut into runs of nearly equal count, one per rank: slabs of the body across its
// longest direction in the usual layout, balanced by points rather than by cells. Every
// rank computes the same partition from the same stencils. It is made again every load
// step, so points that move into another slab change rank with the step.
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

template <int dim>
PointPartition partition_points(const PointStencils<dim>& st, int num_nodes, int ranks) {
  const int np = static_cast<int>(st.size());
  PointPartition part;
  if (ranks == 1) {  // a serial run: every point, in index order
    part.order.resize(np);
    for (int p = 0; p < np; ++p) part.order[p] = p;
    part.start = {0, np};
    return part;
  }
  // A counting sort by the lowest stencil node; points of one node keep index order.
  std::vector<int> key(np), first(num_nodes + 1, 0);
  for (int p = 0; p < np; ++p) {
    int lowest = num_nodes - 1;
    for (int a = 0; a < st[p].count; ++a) lowest = std::min(lowest, st[p].node[a]);
    key[p] = lowest;
    ++first[lowest + 1];
  }
  for (int n = 0; n < num_nodes; ++n) first[n + 1] += first[n];
  part.order.resize(np);
  for (int p = 0; p < np; ++p) part.order[first[key[p]]++] = p;
  part.start.resize(ranks + 1);
  for (int r = 0; r <= ranks; ++r) part.start[r] = static_cast<int>(static_cast<long long>(np) * r / ranks);
  return part;
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
