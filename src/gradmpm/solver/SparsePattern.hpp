#pragma once
// The sparsity pattern of every global operator: dofs i and j couple when some
// material point's stencil holds both nodes. Built once per load step (points move
// between steps, not within one) and then filled by scatter-add, so no triplet
// list is sorted in the Newton loop.
#include <algorithm>
#include <vector>

#include "gradmpm/solver/DofMap.hpp"

namespace gradmpm {

/// Returns a compressed matrix holding the pattern with all values zero.
template <int dim>
SparseMatrix build_pattern(const PointStencils<dim>& st, const DofMap& dofs) {
  const int n_active = dofs.num_active_nodes(), nc = dofs.ncomp();
  std::vector<std::vector<int>> adj(n_active);  // neighbour equations per active node
  for (const auto& s : st)
    for (int a = 0; a < s.count; ++a) {
      auto& row = adj[dofs.dof(s.node[a], 0) / nc];
      for (int b = 0; b < s.count; ++b) row.push_back(dofs.dof(s.node[b], 0) / nc);
    }
  SparseMatrix A(n_active * nc, n_active * nc);
  std::vector<int> nnz_per_col(n_active * nc);
  for (int e = 0; e < n_active; ++e) {
    std::sort(adj[e].begin(), adj[e].end());
    adj[e].erase(std::unique(adj[e].begin(), adj[e].end()), adj[e].end());
    for (int c = 0; c < nc; ++c) nnz_per_col[e * nc + c] = static_cast<int>(adj[e].size()) * nc;
  }
  A.reserve(nnz_per_col);
  for (int e = 0; e < n_active; ++e)  // columns in order, rows sorted: cheap insertBack-like
    for (int c = 0; c < nc; ++c)
      for (int f : adj[e])
        for (int r = 0; r < nc; ++r) A.insert(f * nc + r, e * nc + c) = 0.0;
  A.makeCompressed();
  return A;
}

/// Position of entry (row, col) in A's value array; the entry must be in the pattern.
inline int pattern_offset(const SparseMatrix& A, int row, int col) {
  const int* begin = A.innerIndexPtr() + A.outerIndexPtr()[col];
  const int* end = A.innerIndexPtr() + A.outerIndexPtr()[col + 1];
  return static_cast<int>(std::lower_bound(begin, end, row) - A.innerIndexPtr());
}

}  // namespace gradmpm
