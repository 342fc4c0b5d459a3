#pragma once
// Sums of per-node values over a distributed run's ranks before any equation numbering
// exists (a node's support, a diagonal that decides which nodes a step keeps), at the
// nodes' owners (grid/RankBoxes.hpp) and with neighbour messages only: each rank sends
// its parts at the nodes it touches and others own to their owners (the NBX consensus),
// each owner adds them to its own part, in the senders' rank order, and sends the totals
// back, so every rank that holds a node's total holds the same bits.
#include <cstring>
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
  const int me = ranks::rank(), size = ranks::size();
  std::vector<std::vector<Item>> to(size);
  for (int n = 0; n < static_cast<int>(value.size()); ++n)
    if (touched[n]) {
      const int r = boxes.owner(n);
      if (r != me) to[r].push_back({n, value[n]});
    }
  std::vector<long long> count(size);
  std::vector<Item> items;
  for (int r = 0; r < size; ++r) {
    count[r] = static_cast<long long>(to[r].size());
    items.insert(items.end(), to[r].begin(), to[r].end());
  }
  const ranks::Neighbours to_owners = ranks::neighbours_of(count);
  const std::vector<char> got = ranks::exchange(to_owners, reinterpret_cast<const char*>(items.data()), sizeof(Item));
  std::vector<Item> received(got.size() / sizeof(Item));
  if (!got.empty()) std::memcpy(received.data(), got.data(), got.size());
  for (const Item& item : received) value[item.node] += item.value;
  std::vector<double> totals(received.size());
  for (std::size_t k = 0; k < received.size(); ++k) totals[k] = value[received[k].node];
  const std::vector<char> back =
      ranks::exchange(to_owners.reversed(), reinterpret_cast<const char*>(totals.data()), sizeof(double));
  if (back.size() != items.size() * sizeof(double)) throw std::logic_error("sum_at_owners: the owners' answers do not match");
  for (std::size_t k = 0; k < items.size(); ++k) std::memcpy(&value[items[k].node], back.data() + k * sizeof(double), sizeof(double));
}

}  // namespace gradmpm
