#pragma once
// Equation numbering of the active grid nodes. In the MPM only the nodes whose shape
// functions some point touches take part in a load step (AMPLE's "active nodes");
// the others carry no equation. Equation of (node, component) = eq(node)*ncomp + comp.
#include <algorithm>
#include <stdexcept>
#include <vector>

#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/core/Types.hpp"
#include "gradmpm/points/Transfer.hpp"

namespace gradmpm {

class DofMap {
 public:
  DofMap() = default;

  /// The nodes of the stencils `st`. `rank_nodes`: a distributed run's cut of the grid
  /// nodes (Model::rank_cells: rank r owns nodes [rank_nodes[r], rank_nodes[r + 1]),
  /// ranks + 1 entries), given on every rank with that rank's points' stencils: the
  /// active nodes are then those of every rank's stencils (the same numbering on every
  /// rank), and rank_rows() says which equations each rank owns. Empty: a serial run.
  template <int dim>
  DofMap(const PointStencils<dim>& st, int num_nodes, int ncomp, const std::vector<int>& rank_nodes = {})
      : ncomp_(ncomp), eq_of_node_(num_nodes, -1) {
    for (const auto& s : st)
      for (int a = 0; a < s.count; ++a) eq_of_node_[s.node[a]] = 0;
    if (!rank_nodes.empty()) ranks::max(eq_of_node_.data(), eq_of_node_.size());
    for (int n = 0; n < num_nodes; ++n)
      if (eq_of_node_[n] == 0) {
        eq_of_node_[n] = static_cast<int>(node_of_eq_.size());
        node_of_eq_.push_back(n);
      }
    if (rank_nodes.empty()) {
      if (ranks::distributed())  // each rank would number only its own points' nodes
        throw std::logic_error("DofMap: a distributed run's numbering needs the cut of the grid nodes (Model::rank_cells)");
      return;
    }
    if (static_cast<int>(rank_nodes.size()) != ranks::size() + 1)
      throw std::logic_error("DofMap: a cut of the grid nodes needs one more entry than there are ranks");
    rank_rows_ = rows_of(rank_nodes);
  }

  /// The equations of the active nodes in each run of a cut of the grid nodes (`cut`:
  /// part r is nodes [cut[r], cut[r + 1]), from 0 to num_grid_nodes()): part r's
  /// equations are [rows[r], rows[r + 1]). Nodes are numbered in increasing index, so
  /// the active nodes of a run of node indices are a run of equations.
  std::vector<int> rows_of(const std::vector<int>& cut) const {
    if (cut.size() < 2 || cut.front() != 0 || cut.back() != num_grid_nodes() || !std::is_sorted(cut.begin(), cut.end()))
      throw std::logic_error("DofMap: a cut of the grid nodes must run from 0 to the number of nodes, ascending");
    std::vector<int> rows(cut.size());
    for (std::size_t r = 0; r < cut.size(); ++r)
      rows[r] = static_cast<int>(std::lower_bound(node_of_eq_.begin(), node_of_eq_.end(), cut[r]) - node_of_eq_.begin()) *
                ncomp_;
    return rows;
  }

  /// A distributed run's: rank r owns equations [rank_rows()[r], rank_rows()[r + 1])
  /// (those of the active nodes of its cut); empty in a serial run.
  const std::vector<int>& rank_rows() const { return rank_rows_; }

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
  std::vector<int> rank_rows_;
};

}  // namespace gradmpm
