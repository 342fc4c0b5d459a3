#pragma once
// Sums of per-node values over a distributed run's ranks before any equation numbering
// exists (a node's support, a diagonal that decides which nodes a step keeps), at the
// nodes' owners (grid/RankBoxes.hpp) and with neighbour messages only: each rank sends
// its parts at the nodes it touches and others own to their owners (the NBX consensus),
// each owner adds them to its own part, in the senders' rank order, and sends the totals
// back, so every rank that holds a node's total holds the same bits.
#include <algorithm>
#include <vector>

#include "gradmpm/core/PagedInts.hpp"
#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/grid/RankBoxes.hpp"

namespace gradmpm {

/// value[n]: this rank's part at grid node n (paged: only the pages near this rank's
/// nodes are held); `touched`: the nodes where this rank has a part, ascending.
/// Afterwards value[n] is the sum over the ranks at every node this rank owns or touched;
/// elsewhere it is this rank's part (zero where untouched). Collective.
inline void sum_at_owners(const RankBoxes& boxes, Paged<double>& value, const std::vector<int>& touched) {
  struct Item {
    int node;
    double value;
  };
  const int me = ranks::rank();
  std::vector<std::vector<Item>> to(ranks::size());
  for (const int n : touched) {
    const int r = boxes.owner(n);
    if (r != me) to[r].push_back({n, value[n]});
  }
  const ranks::Sent<Item> s = ranks::send_to(to);
  for (const Item& item : s.received) value.at(item.node) += item.value;
  std::vector<double> totals(s.received.size());
  for (std::size_t k = 0; k < totals.size(); ++k) totals[k] = value[s.received[k].node];
  const std::vector<double> back = ranks::answer(s, totals);
  for (std::size_t k = 0; k < back.size(); ++k) value.set(s.sent[k].node, back[k]);
}

/// The nodes of stencils `st`, ascending, each once.
template <class Stencils>
std::vector<int> stencil_nodes(const Stencils& st) {
  std::vector<int> nodes;
  for (const auto& s : st) nodes.insert(nodes.end(), s.node.begin(), s.node.begin() + s.count);
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  return nodes;
}

}  // namespace gradmpm
