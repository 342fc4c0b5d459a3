#pragma once
// Equation numbering of the active grid nodes. In the MPM only the nodes whose shape
// functions some point touches take part in a load step (AMPLE's "active nodes");
// the others carry no equation. Equation of (node, component) = eq(node)*ncomp + comp.
#include <algorithm>
#include <stdexcept>
#include <vector>

#include "gradmpm/core/PagedInts.hpp"
#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/core/Types.hpp"
#include "gradmpm/grid/RankBoxes.hpp"
#include "gradmpm/points/Transfer.hpp"

namespace gradmpm {

class DofMap {
 public:
  DofMap() = default;

  /// How much of a distributed run's numbering a rank learns.
  /// `every_node`: the active nodes are the union over the ranks of their stencils' nodes
  /// (an all-reduce of one integer per grid node), and every rank knows every node's
  /// equations. A margin m >= 0: each rank learns the equations of the nodes it owns, of
  /// its stencils' nodes, and of the nodes within m node layers of its box (for the
  /// ghost penalty's faces and its grid piece), from their owners: neighbour messages
  /// only. The other nodes read as inactive on that rank (active() false).
  static constexpr int every_node = -1;

  /// The nodes of the stencils `st`. `boxes`: a distributed run's partition of the grid
  /// (Model::rank_boxes: rank r owns the nodes boxes.owner() gives it), given on every
  /// rank with that rank's points' stencils: the active nodes are then those of every
  /// rank's stencils, numbered by their owners, rank after rank, each rank's in
  /// increasing index (the same equation of a node on every rank that knows it: see
  /// `margin` above), and rank_rows() says which equations each rank owns. Empty: a
  /// serial run, the active nodes numbered in increasing index.
  template <int dim>
  DofMap(const PointStencils<dim>& st, int num_nodes, int ncomp, const RankBoxes& boxes = {}, int margin = every_node)
      : ncomp_(ncomp), eq_of_node_(num_nodes, -1) {
    for (const auto& s : st)
      for (int a = 0; a < s.count; ++a) eq_of_node_.set(s.node[a], 0);
    if (boxes.empty()) {
      if (ranks::distributed())  // each rank would number only its own points' nodes
        throw std::logic_error("DofMap: a distributed run's numbering needs the partition of the grid (Model::rank_boxes)");
      // The nodes the stencils reach (in the pages they allocated), in increasing index.
      eq_of_node_.for_each_held([&](int n, int eq) {
        if (eq == 0) node_of_eq_.push_back(n);
      });
      for (std::size_t e = 0; e < node_of_eq_.size(); ++e) eq_of_node_.set(node_of_eq_[e], static_cast<int>(e));
      return;
    }
    if (boxes.size() != ranks::size() || boxes.num_nodes() != num_nodes)
      throw std::logic_error("DofMap: the partition of the grid must have one box per rank and the grid's nodes");
    if (margin >= 0) {
      number_by_owners(boxes, margin);
      return;
    }
    eq_of_node_.allocate_all();  // (the union over the ranks: every page on every rank)
    for (int p = 0; p < eq_of_node_.num_pages(); ++p) ranks::max(eq_of_node_.page(p), PagedInts::page_size);
    // Each owner's active nodes, rank after rank.
    std::vector<int> count(ranks::size() + 1, 0);
    for (int n = 0; n < num_nodes; ++n)
      if (eq_of_node_[n] == 0) ++count[boxes.owner(n) + 1];
    for (int r = 0; r < ranks::size(); ++r) count[r + 1] += count[r];
    node_of_eq_.resize(count.back());
    rank_rows_.resize(count.size());
    for (std::size_t r = 0; r < count.size(); ++r) rank_rows_[r] = count[r] * ncomp_;
    own_first_ = count[ranks::rank()];
    own_last_ = count[ranks::rank() + 1];
    for (int n = 0; n < num_nodes; ++n)
      if (eq_of_node_[n] == 0) {
        const int e = count[boxes.owner(n)]++;
        eq_of_node_.set(n, e);
        node_of_eq_[e] = n;
      }
  }

  /// A distributed run's: rank r owns global equations [rank_rows()[r], rank_rows()[r + 1])
  /// (those of the active nodes of its box); empty in a serial run.
  const std::vector<int>& rank_rows() const { return rank_rows_; }

  /// Numbered by the owners (a margin), a rank's equations are local: its own nodes
  /// first (in global order), then the other nodes it knows, ascending in global
  /// equation, so that its vectors hold its own and ghost rows only. dof(), node_of(),
  /// num_dofs() are local; global_rows() maps them to the global equations (PETSc's rows,
  /// RowHalo). Serially, and with every_node, local equations are global (global_rows() empty).
  std::vector<int> global_rows() const {
    std::vector<int> rows;
    if (global_eq_.empty()) return rows;
    rows.resize(global_eq_.size() * ncomp_);
    for (std::size_t e = 0; e < global_eq_.size(); ++e)
      for (int i = 0; i < ncomp_; ++i) rows[e * ncomp_ + i] = global_eq_[e] * ncomp_ + i;
    return rows;
  }
  /// The global equation of (node, comp) (the same on every rank that knows the node).
  int global_dof(int node, int comp) const {
    const int e = eq_of_node_[node];
    return (global_eq_.empty() ? e : global_eq_[e]) * ncomp_ + comp;
  }
  /// This rank's own nodes: local node equations [own_nodes_first(), own_nodes_last())
  /// (serially every active node).
  int own_nodes_first() const { return rank_rows_.empty() ? 0 : own_first_; }
  int own_nodes_last() const { return rank_rows_.empty() ? num_active_nodes() : own_last_; }
  /// Equations of the whole system, over every rank (serially num_dofs()).
  int num_global_dofs() const { return rank_rows_.empty() ? num_dofs() : rank_rows_.back(); }

  int ncomp() const { return ncomp_; }
  int num_active_nodes() const { return static_cast<int>(node_of_eq_.size()); }
  int num_dofs() const { return num_active_nodes() * ncomp_; }
  int num_grid_nodes() const { return static_cast<int>(eq_of_node_.size()); }
  /// Bytes the node-to-equation map holds (pages near the nodes this rank knows only).
  std::size_t node_map_bytes() const { return eq_of_node_.bytes(); }
  bool active(int node) const { return eq_of_node_[node] >= 0; }
  int dof(int node, int comp) const { return eq_of_node_[node] * ncomp_ + comp; }
  int node_of(int eq) const { return node_of_eq_[eq]; }

  /// A permutation of the equations (an elimination order) from an order of grid nodes:
  /// the active nodes among `nodes` in that order, each node's equations together, then
  /// the active nodes `nodes` leaves out, in equation order. Nodes outside the grid or
  /// inactive are skipped (an order carried from another step or system).
  std::vector<int> equations_in_node_order(const std::vector<int>& nodes) const {
    std::vector<char> placed(num_active_nodes(), 0);
    std::vector<int> perm;
    perm.reserve(num_dofs());
    const auto place = [&](int e) {
      if (placed[e]) return;
      placed[e] = 1;
      for (int c = 0; c < ncomp_; ++c) perm.push_back(e * ncomp_ + c);
    };
    for (const int node : nodes)
      if (node >= 0 && node < num_grid_nodes() && active(node)) place(eq_of_node_[node]);
    for (int e = 0; e < num_active_nodes(); ++e) place(e);
    return perm;
  }

  /// A vector in equation numbering at every grid node, ncomp values per node (zero on
  /// inactive nodes).
  Vector to_grid_all(const Vector& v) const {
    Vector u = Vector::Zero(static_cast<Eigen::Index>(num_grid_nodes()) * ncomp_);
    for (int e = 0; e < num_active_nodes(); ++e)
      if (node_of_eq_[e] >= 0)  // (a rank's numbering by its owners: a node it does not know)
        for (int i = 0; i < ncomp_; ++i) u[node_of_eq_[e] * ncomp_ + i] = v[e * ncomp_ + i];
    return u;
  }

  /// The active nodes' coordinates, one row per node in equation order (zero for a node
  /// this rank does not know).
  template <int dim>
  Eigen::MatrixXd coordinates(const Grid<dim>& grid) const {
    Eigen::MatrixXd x = Eigen::MatrixXd::Zero(num_active_nodes(), dim);
    for (int e = 0; e < num_active_nodes(); ++e)
      if (node_of_eq_[e] >= 0) x.row(e) = grid.node_position(node_of_eq_[e]).transpose();
    return x;
  }

  /// Expands a vector in equation numbering (one component) to all grid nodes,
  /// inactive nodes getting `fill`.
  Vector to_grid(const Vector& v, int comp = 0, double fill = 0.0) const {
    Vector g = Vector::Constant(num_grid_nodes(), fill);
    for (int e = 0; e < num_active_nodes(); ++e)
      if (node_of_eq_[e] >= 0) g[node_of_eq_[e]] = v[e * ncomp_ + comp];
    return g;
  }

 private:
  /// Each rank numbers the active nodes of its box after the ranks before it: the nodes
  /// its stencils reach in other boxes (and those within `margin` node layers of its box)
  /// are sent to their owners (the NBX consensus: neighbours only), which mark the
  /// reached ones active, number their own, and answer each node's equation (or -1:
  /// inactive).
  void number_by_owners(const RankBoxes& boxes, int margin) {
    const int me = ranks::rank(), size = ranks::size(), num_nodes = num_grid_nodes();
    // The nodes this rank needs from others, ascending, grouped by owner in rank order,
    // each with whether its stencils reach it.
    struct Ask {
      int node, reached;
    };
    // Only nodes the stencils reach (in the pages they allocated) or near the box can be
    // asked for: those are visited, not the whole grid (a rank's box and its neighbours'
    // edges, where the grid may have 1e8 nodes).
    std::vector<int> candidates;
    eq_of_node_.for_each_held([&](int n, int eq) {
      if (eq == 0) candidates.push_back(n);
    });
    const std::size_t reached_count = candidates.size();
    boxes.for_each_node_near(me, margin, [&](int n) {
      if (eq_of_node_[n] != 0) candidates.push_back(n);  // (the reached ones are listed)
    });
    std::inplace_merge(candidates.begin(), candidates.begin() + reached_count, candidates.end());
    std::vector<std::vector<Ask>> to(size);
    for (const int n : candidates) {
      const int r = boxes.owner(n);
      if (r == me) continue;
      to[r].push_back({n, eq_of_node_[n] == 0 ? 1 : 0});
    }
    const ranks::Sent<Ask> asked = ranks::send_to(to);
    for (const Ask& a : asked.received) {
      if (a.node < 0 || a.node >= num_nodes || boxes.owner(a.node) != me)
        throw std::logic_error("DofMap: a rank asked for a node this rank does not own");
      if (a.reached) eq_of_node_.set(a.node, 0);
    }
    // This rank's nodes, numbered after the ranks before it (global equations).
    int own = 0;
    boxes.for_each_node(me, [&](int n) { own += eq_of_node_[n] == 0; });
    const std::vector<int> counts = ranks::all_gather({own});
    int offset = 0;
    rank_rows_.assign(size + 1, 0);
    for (int r = 0; r < size; ++r) {
      if (r < me) offset += counts[r];
      rank_rows_[r + 1] = rank_rows_[r] + counts[r] * ncomp_;
    }
    int e = offset;
    boxes.for_each_node(me, [&](int n) {
      if (eq_of_node_[n] == 0) eq_of_node_.set(n, e++);
    });
    // The answers: each asked node's global equation (or -1), back in the order asked.
    std::vector<int> answers(asked.received.size());
    for (std::size_t k = 0; k < answers.size(); ++k) answers[k] = eq_of_node_[asked.received[k].node];
    const std::vector<int> eq = ranks::answer(asked, answers);
    // Local equations: the own nodes (global offset + k -> k), then the others known, by
    // increasing global equation.
    std::vector<std::pair<int, int>> others;  // (global equation, node)
    for (std::size_t k = 0; k < eq.size(); ++k) {
      eq_of_node_.set(asked.sent[k].node, eq[k]);
      if (eq[k] >= 0) others.emplace_back(eq[k], asked.sent[k].node);
    }
    std::sort(others.begin(), others.end());
    own_first_ = 0;
    own_last_ = own;
    node_of_eq_.assign(own + others.size(), -1);
    global_eq_.assign(node_of_eq_.size(), -1);
    boxes.for_each_node(me, [&](int n) {
      if (eq_of_node_[n] >= 0) {
        const int local = eq_of_node_[n] - offset;
        eq_of_node_.set(n, local);
        node_of_eq_[local] = n;
        global_eq_[local] = offset + local;
      }
    });
    for (std::size_t k = 0; k < others.size(); ++k) {
      const int local = own + static_cast<int>(k);
      eq_of_node_.set(others[k].second, local);
      node_of_eq_[local] = others[k].second;
      global_eq_[local] = others[k].first;
    }
  }

  int ncomp_ = 1;
  /// Node -> equation (-1: inactive or unknown): pages only where this rank's nodes are.
  PagedInts eq_of_node_;
  std::vector<int> node_of_eq_;
  std::vector<int> global_eq_;  ///< local node equation -> global (empty: the same)
  int own_first_ = 0, own_last_ = 0;  ///< this rank's own nodes' local equations
  std::vector<int> rank_rows_;
};

}  // namespace gradmpm
