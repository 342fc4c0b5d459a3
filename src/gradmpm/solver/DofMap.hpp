#pragma once
// Equation numbering of the active grid nodes. In the MPM only the nodes whose shape
// functions some point touches take part in a load step (AMPLE's "active nodes");
// the others carry no equation. Equation of (node, component) = eq(node)*ncomp + comp.
#include <vector>

#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/core/Types.hpp"
#include "gradmpm/points/Transfer.hpp"

namespace gradmpm {

class DofMap {
 public:
  DofMap() = default;

  /// The nodes of the stencils `st`; `over_ranks`: of every rank's stencils (they are a
  /// distributed run's rank's points': the same numbering on every rank).
  template <int dim>
  DofMap(const PointStencils<dim>& st, int num_nodes, int ncomp, bool over_ranks = false)
      : ncomp_(ncomp), eq_of_node_(num_nodes, -1) {
    for (const auto& s : st)
      for (int a = 0; a < s.count; ++a) eq_of_node_[s.node[a]] = 0;
    if (over_ranks) ranks::max(eq_of_node_.data(), eq_of_node_.size());
    for (int n = 0; n < num_nodes; ++n)
      if (eq_of_node_[n] == 0) {
        eq_of_node_[n] = static_cast<int>(node_of_eq_.size());
        node_of_eq_.push_back(n);
      }
  }

  int ncomp() const { return ncomp_; }
  int num_active_nodes() const { return static_cast<int>(node_of_eq_.size()); }
  int num_dofs() const { return num_active_nodes() * ncomp_; }
  int num_grid_nodes() const { return static_cast<int>(eq_of_node_.size()); }
  bool active(int node) const { return eq_of_node_[node] >= 0; }
  int dof(int node, int comp) const { return eq_of_node_[node] * ncomp_ + comp; }
  int node_of(int eq) const { return node_of_eq_[eq]; }

  /// A vector in equation numbering at every grid node, ncomp values per node (zero on
  /// inactive nodes).
  Vector to_grid_all(const Vector& v) const {
    Vector u = Vector::Zero(static_cast<Eigen::Index>(num_grid_nodes()) * ncomp_);
    for (int e = 0; e < num_active_nodes(); ++e)
      for (int i = 0; i < ncomp_; ++i) u[node_of_eq_[e] * ncomp_ + i] = v[e * ncomp_ + i];
    return u;
  }

  /// The active nodes' coordinates, one row per node in equation order.
  template <int dim>
  Eigen::MatrixXd coordinates(const Grid<dim>& grid) const {
    Eigen::MatrixXd x(num_active_nodes(), dim);
    for (int e = 0; e < num_active_nodes(); ++e) x.row(e) = grid.node_position(node_of_eq_[e]).transpose();
    return x;
  }

  /// Expands a vector in equation numbering (one component) to all grid nodes,
  /// inactive nodes getting `fill`.
  Vector to_grid(const Vector& v, int comp = 0, double fill = 0.0) const {
    Vector g = Vector::Constant(num_grid_nodes(), fill);
    for (int e = 0; e < num_active_nodes(); ++e) g[node_of_eq_[e]] = v[e * ncomp_ + comp];
    return g;
  }

 private:
  int ncomp_ = 1;
  std::vector<int> eq_of_node_;
  std::vector<int> node_of_eq_;
};

}  // namespace gradmpm
