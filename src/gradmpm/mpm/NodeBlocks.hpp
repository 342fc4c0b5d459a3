#pragma once
// The load step's equations (dim per node) grown by one more unknown per node: the
// two-field steps that wrap the solid's (the pore pressure of mpm/Consolidation.hpp, the
// nonlocal plastic strain of mpm/GradientCoupling.hpp) number node e's unknowns
// e * (dim + 1) + i, the solid's du first and the extra field's last. Internal to the driver.
#include <Eigen/SparseCore>

#include <algorithm>
#include <utility>
#include <vector>

#include "gradmpm/core/Types.hpp"

namespace gradmpm::detail {

/// The solid's pattern K (dim per node, node blocks) with each node block grown to
/// nc x nc; values zero.
template <int dim, int nc>
SparseMatrix grown_pattern(const SparseMatrix& K, int nodes) {
  const int* outer = K.outerIndexPtr();
  const int* inner = K.innerIndexPtr();
  std::vector<int> out_outer(static_cast<std::size_t>(nodes) * nc + 1, 0), out_inner;
  out_inner.reserve(static_cast<std::size_t>(K.nonZeros()) * nc * nc / (dim * dim) + 1);
  for (int e = 0; e < nodes; ++e) {
    const int col = e * dim;
    for (int c = 0; c < nc; ++c) {
      for (int j = outer[col]; j < outer[col + 1]; j += dim) {
        const int block = inner[j] / dim;
        for (int r = 0; r < nc; ++r) out_inner.push_back(block * nc + r);
      }
      out_outer[e * nc + c + 1] = static_cast<int>(out_inner.size());
    }
  }
  const int n = nodes * nc;
  std::vector<double> values(out_inner.size(), 0.0);
  return Eigen::Map<const SparseMatrix>(n, n, static_cast<int>(out_inner.size()), out_outer.data(), out_inner.data(),
                                        values.data());
}

/// Adds the solid's matrix K (dim per node) into the node blocks of T (grown_pattern's).
template <int dim, int nc>
void add_node_blocks(const SparseMatrix& K, SparseMatrix& T) {
  const int* outer = K.outerIndexPtr();
  const double* kv = K.valuePtr();
  const int* t_outer = T.outerIndexPtr();
  double* tv = T.valuePtr();
  for (int col = 0; col < K.outerSize(); ++col) {
    const int e = col / dim, i = col % dim;
    const int begin = t_outer[e * nc + i];
    for (int j = 0; j < outer[col + 1] - outer[col]; ++j) tv[begin + (j / dim) * nc + j % dim] += kv[outer[col] + j];
  }
}

/// The combined step's constraints: the solid's (`solid` in its numbering, dim per node,
/// with their `increments`) and the extra field's `extra` (combined numbering, increment),
/// in ascending order of equation, one per equation (of equal ones, the smallest increment).
template <int dim>
void node_block_constraints(const std::vector<int>& solid, const std::vector<double>& increments,
                            std::vector<std::pair<int, double>> extra, std::vector<int>& dofs,
                            std::vector<double>& values) {
  constexpr int nc = dim + 1;
  for (std::size_t k = 0; k < solid.size(); ++k) extra.push_back({(solid[k] / dim) * nc + solid[k] % dim, increments[k]});
  std::sort(extra.begin(), extra.end());
  extra.erase(std::unique(extra.begin(), extra.end(), [](const auto& a, const auto& b) { return a.first == b.first; }),
              extra.end());
  dofs.clear();
  values.clear();
  for (const auto& [dof, value] : extra) {
    dofs.push_back(dof);
    values.push_back(value);
  }
}

/// The solid's du (dim per node) and the extra field (one per node) of the combined x.
template <int dim>
void split_node_blocks(const Vector& x, Vector& du, Vector& extra) {
  constexpr int nc = dim + 1;
  const Eigen::Index nodes = x.size() / nc;
  du.resize(nodes * dim);
  extra.resize(nodes);
  for (Eigen::Index e = 0; e < nodes; ++e) {
    for (int i = 0; i < dim; ++i) du[e * dim + i] = x[e * nc + i];
    extra[e] = x[e * nc + dim];
  }
}

}  // namespace gradmpm::detail
