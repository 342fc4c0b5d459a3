#pragma once
// The sparsity pattern of every global operator: dofs i and j couple when some
// material point's stencil holds both nodes. Built once per load step (points move
// between steps, not within one) and then filled by scatter-add, so no triplet
// list is sorted in the Newton loop.
#include <algorithm>
#include <vector>

#include "gradmpm/solver/DofMap.hpp"

namespace gradmpm {

/// Returns a compressed matrix holding the pattern with all values zero. Node by node:
/// the points touching a node (an incidence list) name its neighbours, which are
/// collected once each with a stamp array and sorted (a couple of dozen per node), and
/// written straight into the compressed arrays.
/// Groups of nodes couple all their nodes (a point's stencil; with F-bar, a cell's
/// points' stencils together): `count(g)` and `node(g, a)` describe group g.
template <class Count, class Node>
SparseMatrix build_pattern_of_groups(int groups, Count&& count, Node&& node, const DofMap& dofs) {
  const int n_active = dofs.num_active_nodes(), nc = dofs.ncomp();
  auto eq = [&](int node) { return dofs.dof(node, 0) / nc; };
  // Groups touching each active node, as compressed lists.
  std::vector<int> first(n_active + 1, 0);
  for (int g = 0; g < groups; ++g)
    for (int a = 0; a < count(g); ++a) ++first[eq(node(g, a)) + 1];
  for (int e = 0; e < n_active; ++e) first[e + 1] += first[e];
  std::vector<int> touching(first[n_active]), fill(first);  // fill[e]: next free slot of node e
  for (int g = 0; g < groups; ++g)
    for (int a = 0; a < count(g); ++a) touching[fill[eq(node(g, a))]++] = g;
  // Neighbour equations of each active node.
  std::vector<int> nbr_first(n_active + 1, 0), nbrs, stamp(n_active, -1);
  nbrs.reserve(static_cast<std::size_t>(n_active) * 25);
  for (int e = 0; e < n_active; ++e) {
    const std::size_t begin = nbrs.size();
    for (int k = first[e]; k < first[e + 1]; ++k) {
      const int g = touching[k];
      for (int b = 0; b < count(g); ++b) {
        const int f = eq(node(g, b));
        if (stamp[f] != e) {
          stamp[f] = e;
          nbrs.push_back(f);
        }
      }
    }
    std::sort(nbrs.begin() + begin, nbrs.end());
    nbr_first[e + 1] = static_cast<int>(nbrs.size());
  }
  // Compressed column storage: column (e, c) holds rows (f, r) for every neighbour f.
  const int n = n_active * nc;
  SparseMatrix A(n, n);
  A.resizeNonZeros(static_cast<Eigen::Index>(nbrs.size()) * nc * nc);
  int* outer = A.outerIndexPtr();
  int* inner = A.innerIndexPtr();
  int k = 0;
  for (int e = 0; e < n_active; ++e)
    for (int c = 0; c < nc; ++c) {
      outer[e * nc + c] = k;
      for (int m = nbr_first[e]; m < nbr_first[e + 1]; ++m)
        for (int r = 0; r < nc; ++r) inner[k++] = nbrs[m] * nc + r;
    }
  outer[n] = k;
  std::fill(A.valuePtr(), A.valuePtr() + k, 0.0);
  return A;
}

/// The pattern of the point stencils.
template <int dim>
SparseMatrix build_pattern(const PointStencils<dim>& st, const DofMap& dofs) {
  return build_pattern_of_groups(
      static_cast<int>(st.size()), [&](int p) { return st[p].count; }, [&](int p, int a) { return st[p].node[a]; },
      dofs);
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
