#pragma once
// Sums of per-node values over a distributed run's ranks before any equation numbering
// exists (a node's support, a diagonal that decides which nodes a step keeps), at the
// nodes' owners (grid/RankBoxes.hpp) and with neighbour messages only: each rank sends
// its parts at the nodes it touches and others own to their owners (the NBX consensus),
// each owner adds them to its own part, in the senders' rank order, and sends the totals
// back, so every rank that holds a node's total holds the same bits.
#include <vector>

#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/grid/RankBoxes.hpp"

namespace gradmpm {

/// value[n]: this rank's part at grid node n; touched[n]: whether this rank has a part
/// there. Afterwards value[n] is the sum over the ranks at every node this rank owns or
/// touched; elsewhere it is this rank's part (zero where untouched). Collective.
inline void sum_at_owners(const RankBoxes& boxes, std::vector<double>& value, const std::vector<char>& touched) {
  struct Item {
    int node;
    double value;
  };
  const int me = ranks::rank();
  std::vector<std::vector<Item>> to(ranks::size());
  for (int n = 0; n < static_cast<int>(value.size()); ++n)
    if (touched[n]) {
      const int r = boxes.owner(n);
      if (r != me) to[r].push_back({n, value[n]});
    }
  const ranks::Sent<Item> s = ranks::send_to(to);
  for (const Item& item : s.received) value[item.node] += item.value;
  std::vector<double> totals(s.received.size());
  for (std::size_t k = 0; k < totals.size(); ++k) totals[k] = value[s.received[k].node];
  const std::vector<double> back = ranks::answer(s, totals);
  for (std::size_t k = 0; k < back.size(); ++k) value[s.sent[k].node] = back[k];
}

}  // namespace gradmpm
