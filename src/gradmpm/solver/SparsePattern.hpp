#pragma once
// The sparsity pattern of every global operator: dofs i and j couple when some
// material point's stencil holds both nodes. Built once per load step (points move
// between steps, not within one) and then filled by scatter-add, so no triplet
// list is sorted in the Newton loop.
#include <algorithm>
#include <vector>

#include "gradmpm/core/Parallel.hpp"
#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/solver/DofMap.hpp"

namespace gradmpm {

/// Returns a compressed matrix holding the pattern with all values zero. Node by node:
/// the points touching a node (an incidence list) name its neighbours, which are
/// collected once each with a stamp array and sorted (a couple of dozen per node), and
/// written straight into the compressed arrays. The neighbour lists and the compressed
/// arrays are made on threads, each over a contiguous range of nodes; the result does
/// not depend on them. Their scratch is allocated before the parallel region (inside it,
/// it cost 6 ms at 1e5 dof in 2D); the figures are in docs/performance.md.
/// Groups of nodes couple all their nodes (a point's stencil; with F-bar, a cell's
/// points' stencils together): `count(g)` and `node(g, a)` describe group g.
template <class Count, class Node>
SparseMatrix build_pattern_of_groups(int groups, Count&& count, Node&& node, const DofMap& dofs) {
  const int n_active = dofs.num_active_nodes(), nc = dofs.ncomp();
  auto eq = [&](int node) { return dofs.dof(node, 0) / nc; };
  // A group with the nodes of the one before adds nothing (the points of a cell often
  // share their stencil): only the others are kept, as compact lists of their nodes'
  // equations (group k's are eqs[group_first[k] .. group_first[k + 1])), so the loops
  // below read contiguous memory, not the stencils.
  // Chunks of the groups on the threads (the groups are read where they lie, 50 MB of
  // stencils for 2e5 points in 2D), then joined in order: the same lists as one pass.
  const bool threaded = use_threads(groups);
  const int chunks = threaded ? max_threads() : 1;
  std::vector<std::vector<int>> chunk_eqs(chunks), chunk_ends(chunks);
#pragma omp parallel for schedule(static, 1) if (threaded)
  for (int t = 0; t < chunks; ++t) {
    const int begin = static_cast<int>(static_cast<long>(groups) * t / chunks);
    const int end = static_cast<int>(static_cast<long>(groups) * (t + 1) / chunks);
    std::vector<int>& e = chunk_eqs[t];
    e.reserve(end > begin ? static_cast<std::size_t>(end - begin) * count(begin) : 0);
    for (int g = begin; g < end; ++g) {
      bool same = g > 0 && count(g) == count(g - 1);
      for (int a = 0; same && a < count(g); ++a) same = node(g, a) == node(g - 1, a);
      if (same) continue;
      for (int a = 0; a < count(g); ++a) e.push_back(eq(node(g, a)));
      chunk_ends[t].push_back(static_cast<int>(e.size()));
    }
  }
  std::vector<int> group_first{0}, eqs;
  std::size_t kept = 0, listed = 0;
  for (int t = 0; t < chunks; ++t) {
    kept += chunk_ends[t].size();
    listed += chunk_eqs[t].size();
  }
  group_first.reserve(kept + 1);
  eqs.reserve(listed);
  for (int t = 0; t < chunks; ++t) {
    const int offset = static_cast<int>(eqs.size());
    eqs.insert(eqs.end(), chunk_eqs[t].begin(), chunk_eqs[t].end());
    for (const int end : chunk_ends[t]) group_first.push_back(offset + end);
  }
  const int distinct = static_cast<int>(group_first.size()) - 1;
  // Groups touching each active node, as compressed lists.
  std::vector<int> first(n_active + 1, 0);
  for (int e : eqs) ++first[e + 1];
  for (int e = 0; e < n_active; ++e) first[e + 1] += first[e];
  std::vector<int> touching(first[n_active]), fill(first);  // fill[e]: next free slot of node e
  for (int k = 0; k < distinct; ++k)
    for (int m = group_first[k]; m < group_first[k + 1]; ++m) touching[fill[eqs[m]]++] = k;
  // Neighbour equations of each active node: chunk t of the nodes into nbrs[t].
  std::vector<std::vector<int>> nbrs(chunks), stamps(chunks, std::vector<int>(n_active, -1));
  std::vector<int> nbr_count(n_active);
  auto chunk_begin = [&](int t) { return static_cast<int>(static_cast<long>(n_active) * t / chunks); };
  for (int t = 0; t < chunks; ++t) nbrs[t].reserve(static_cast<std::size_t>(chunk_begin(t + 1) - chunk_begin(t)) * 25);
#pragma omp parallel for schedule(static, 1) if (threaded)
  for (int t = 0; t < chunks; ++t) {
    std::vector<int>& stamp = stamps[t];
    auto& list = nbrs[t];
    for (int e = chunk_begin(t); e < chunk_begin(t + 1); ++e) {
      const std::size_t begin = list.size();
      for (int k = first[e]; k < first[e + 1]; ++k) {
        const int g = touching[k];
        for (int m = group_first[g]; m < group_first[g + 1]; ++m) {
          const int f = eqs[m];
          if (stamp[f] != e) {
            stamp[f] = e;
            list.push_back(f);
          }
        }
      }
      std::sort(list.begin() + begin, list.end());
      nbr_count[e] = static_cast<int>(list.size() - begin);
    }
  }
  // Compressed column storage: column (e, c) holds rows (f, r) for every neighbour f.
  std::vector<long> entries_before(n_active + 1, 0);  // nc^2 entries per neighbour pair
  for (int e = 0; e < n_active; ++e)
    entries_before[e + 1] = entries_before[e] + static_cast<long>(nbr_count[e]) * nc * nc;
  const int n = n_active * nc;
  SparseMatrix A(n, n);
  A.resizeNonZeros(static_cast<Eigen::Index>(entries_before[n_active]));
  int* outer = A.outerIndexPtr();
  int* inner = A.innerIndexPtr();
  double* values = A.valuePtr();
#pragma omp parallel for schedule(static, 1) if (threaded)
  for (int t = 0; t < chunks; ++t) {
    const int* f = nbrs[t].data();
    for (int e = chunk_begin(t); e < chunk_begin(t + 1); ++e) {
      const int m = nbr_count[e];
      for (int c = 0; c < nc; ++c) {
        int k = static_cast<int>(entries_before[e]) + c * m * nc;
        outer[e * nc + c] = k;
        for (int j = 0; j < m; ++j)
          for (int r = 0; r < nc; ++r) inner[k++] = f[j] * nc + r;
      }
      std::fill(values + entries_before[e], values + entries_before[e + 1], 0.0);
      f += m;
    }
  }
  outer[n] = static_cast<int>(entries_before[n_active]);
  return A;
}

/// The pattern of the point stencils.
template <int dim>
SparseMatrix build_pattern(const PointStencils<dim>& st, const DofMap& dofs) {
  return build_pattern_of_groups(
      static_cast<int>(st.size()), [&](int p) { return st[p].count; }, [&](int p, int a) { return st[p].node[a]; },
      dofs);
}

/// The pattern of this rank's share of an operator assembled from the stencils `st` of
/// its points (a distributed run's rank's own, mpm/RankPoints.hpp): their stencils, and
/// the diagonal block of every active node in its rows (DofMap::rank_rows) too: the
/// share of a row's owner holds its constrained diagonal (DirichletElimination with a
/// RowHalo); the solver adds the ranks' patterns up. A serial run's is build_pattern()'s.
template <int dim>
SparseMatrix build_rank_pattern(const PointStencils<dim>& st, const DofMap& dofs) {
  if (!ranks::distributed()) return build_pattern(st, dofs);
  const int n_points = static_cast<int>(st.size());
  const int first = dofs.own_nodes_first(), last = dofs.own_nodes_last();
  return build_pattern_of_groups(
      n_points + (last - first), [&](int g) { return g < n_points ? st[g].count : 1; },
      [&](int g, int a) { return g < n_points ? st[g].node[a] : dofs.node_of(first + g - n_points); }, dofs);
}

/// The pattern of node groups given as lists.
inline SparseMatrix build_pattern(const std::vector<std::vector<int>>& groups, const DofMap& dofs) {
  return build_pattern_of_groups(
      static_cast<int>(groups.size()), [&](int g) { return static_cast<int>(groups[g].size()); },
      [&](int g, int a) { return groups[g][a]; }, dofs);
}

/// Position of entry (row, col) in A's value array; the entry must be in the pattern.
inline int pattern_offset(const SparseMatrix& A, int row, int col) {
  const int* begin = A.innerIndexPtr() + A.outerIndexPtr()[col];
  const int* end = A.innerIndexPtr() + A.outerIndexPtr()[col + 1];
  return static_cast<int>(std::lower_bound(begin, end, row) - A.innerIndexPtr());
}

}  // namespace gradmpm
