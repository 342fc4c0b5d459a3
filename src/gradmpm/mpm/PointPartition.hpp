#pragma once
// Which rank does which points' work (a distributed run, core/Ranks.hpp). Each point has
// a key, a grid node (the lower corner of its cell, mpm/RankPoints.hpp). Nodes are numbered x fastest, so
// ordering the points by key orders them by the grid's slowest axis first; they are cut
// into runs of nearly equal count, one per rank, at key boundaries only, so points of one
// key share a rank. Every rank computes the same partition from the same keys.
#include <algorithm>
#include <limits>
#include <vector>

#include "gradmpm/core/Ranks.hpp"

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

/// A distributed run's failed point: the lowest `point` over the ranks (`none` where no
/// rank has one) and the `value` its owner found for it, on every rank.
inline void lowest_over_ranks(int& point, double& value, int none = std::numeric_limits<int>::max()) {
  const int lowest = ranks::min(point);
  double v = lowest == point ? value : 0.0;  // points are unique to ranks: one owner adds it
  if (lowest < none) ranks::sum(&v, 1);
  point = lowest;
  value = v;
}

}  // namespace gradmpm
