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
template <int dim>
SparseMatrix build_pattern(const PointStencils<dim>& st, const DofMap& dofs) {
  const int n_active = dofs.num_active_nodes(), nc = dofs.ncomp();
  auto eq = [&](int node) { return dofs.dof(node, 0) / nc; };
  // Points touching each active node, as compressed lists.
  std::vector<int> first(n_active + 1, 0);
  for (const auto& s : st)
    for (int a = 0; a < s.count; ++a) ++first[eq(s.node[a]) + 1];
  for (int e = 0; e < n_active; ++e) first[e + 1] += first[e];
  std::vector<int> touching(first[n_active]), fill(first);  // fill[e]: next free slot of node e
  for (int p = 0; p < static_cast<int>(st.size()); ++p)
    for (int a = 0; a < st[p].count; ++a) touching[fill[eq(st[p].node[a])]++] = p;
  // Neighbour equations of each active node.
  std::vector<int> nbr_first(n_active + 1, 0), nbrs, stamp(n_active, -1);
  nbrs.reserve(static_cast<std::size_t>(n_active) * ipow(5, dim));
  for (int e = 0; e < n_active; ++e) {
    const std::size_t begin = nbrs.size();
    for (int k = first[e]; k < first[e + 1]; ++k) {
      const auto& s = st[touching[k]];
      for (int b = 0; b < s.count; ++b) {
        const int f = eq(s.node[b]);
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

/// Position of entry (row, col) in A's value array; the entry must be in the pattern.
inline int pattern_offset(const SparseMatrix& A, int row, int col) {
  const int* begin = A.innerIndexPtr() + A.outerIndexPtr()[col];
  const int* end = A.innerIndexPtr() + A.outerIndexPtr()[col + 1];
  return static_cast<int>(std::lower_bound(begin, end, row) - A.innerIndexPtr());
}

}  // namespace gradmpm
