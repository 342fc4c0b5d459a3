#pragma once
// How a distributed run's points move between ranks (docs/parallel.md).
//
// Each rank owns the points in its box of the grid's cells (mpm/RankPoints.hpp) and holds
// only them, with every per-point array that goes with them: the points' own arrays and
// state block (Model::points), their ids in the whole body (Model::point_ids) and what a
// post-step stage carries at them (the gradient step's accumulated fields). When points
// change owner, one PointMigration says how, and is applied to each of those arrays in
// turn. Who sends to whom is found once per migration (ranks::neighbours_of: messages
// to the ranks a rank sends to, no all-to-all); each array is then one message to each of
// those ranks, and a rank's points are always listed in increasing id, so the same points
// give the same arrays whichever way they came (a restarted run, a collection and back).
//
// Uses: keep (a run whose every rank holds every point, just read or restored, keeps its
// own: no communication), to the owners after a converged step (the points that crossed
// into another rank's cells, to a neighbour; most stay), the points by runs of ids for
// the final CSV files, and every point to rank 0 (output.check's verification).
#include <algorithm>
#include <cstring>
#include <numeric>
#include <type_traits>
#include <vector>

#include "gradmpm/core/Ranks.hpp"

namespace gradmpm {

class PointMigration {
 public:
  /// This rank keeps its points at the positions `kept` (increasing), nothing is sent.
  static PointMigration keep(std::vector<int> kept) {
    PointMigration m;
    m.local_ = true;
    m.order_ = std::move(kept);
    return m;
  }

  /// Point p of this rank (id ids[p], ids increasing) goes to rank dest[p]; the points a
  /// rank ends with are listed in increasing id. A collective call.
  static PointMigration exchange(const std::vector<int>& dest, const std::vector<int>& ids) {
    PointMigration m;
    const int size = ranks::size();
    m.send_counts_.assign(size, 0);
    for (const int r : dest) ++m.send_counts_[r];
    m.neighbours_ = ranks::neighbours_of(std::vector<long long>(m.send_counts_.begin(), m.send_counts_.end()));
    // This rank's points grouped by destination, in increasing id within each group.
    std::vector<int> start(size + 1, 0);
    for (int r = 0; r < size; ++r) start[r + 1] = start[r] + m.send_counts_[r];
    m.send_order_.resize(dest.size());
    for (std::size_t p = 0; p < dest.size(); ++p) m.send_order_[start[dest[p]]++] = static_cast<int>(p);
    // The ids travel first; the order that sorts the received ids is every array's order.
    std::vector<int> sent_ids(ids), received_ids;
    m.move(sent_ids, 1, received_ids, /*sorted=*/false);
    m.order_.resize(received_ids.size());
    std::iota(m.order_.begin(), m.order_.end(), 0);
    std::sort(m.order_.begin(), m.order_.end(), [&](int a, int b) { return received_ids[a] < received_ids[b]; });
    m.ids_.resize(received_ids.size());
    for (std::size_t k = 0; k < m.order_.size(); ++k) m.ids_[k] = received_ids[m.order_[k]];
    return m;
  }

  /// The ids of the points this rank holds after the migration (exchange only).
  const std::vector<int>& ids() const { return ids_; }
  /// Points this rank sent to another rank (exchange only).
  int sent() const {
    int n = 0;
    for (std::size_t r = 0; r < send_counts_.size(); ++r)
      if (static_cast<int>(r) != ranks::rank()) n += send_counts_[r];
    return n;
  }

  /// Moves `a`, per_point values of T per point (T: double, int, a fixed-size Eigen type
  /// of doubles), as the migration says. A collective call for an exchange.
  template <class T>
  void apply(std::vector<T>& a, int per_point = 1) const {
    // (Eigen's fixed-size matrices declare copy constructors but are plain arrays of doubles.)
    static_assert(std::is_standard_layout_v<T> && sizeof(T) % sizeof(int) == 0, "points' arrays travel as bytes");
    if (local_) {
      std::vector<T> kept(order_.size() * static_cast<std::size_t>(per_point));
      for (std::size_t k = 0; k < order_.size(); ++k)
        std::copy_n(a.begin() + static_cast<std::size_t>(order_[k]) * per_point, per_point,
                    kept.begin() + k * per_point);
      a = std::move(kept);
      return;
    }
    std::vector<T> received;
    move(a, per_point, received, /*sorted=*/true);
    a = std::move(received);
  }

 private:
  PointMigration() = default;

  /// Sends a's rows by destination; `out` gets the received rows, in increasing id when
  /// `sorted` (else as received: rank order).
  template <class T>
  void move(const std::vector<T>& a, int per_point, std::vector<T>& out, bool sorted) const {
    const std::size_t row = sizeof(T) * per_point;
    std::vector<char> send(send_order_.size() * row);
    for (std::size_t k = 0; k < send_order_.size(); ++k)
      std::memcpy(send.data() + k * row, a.data() + static_cast<std::size_t>(send_order_[k]) * per_point, row);
    const std::vector<char> got = ranks::exchange(neighbours_, send.data(), row);
    const std::size_t n = static_cast<std::size_t>(neighbours_.received());
    out.resize(n * per_point);
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t from = sorted ? static_cast<std::size_t>(order_[k]) : k;
      std::memcpy(static_cast<void*>(out.data() + k * per_point), got.data() + from * row, row);
    }
  }

  bool local_ = false;
  std::vector<int> order_;                     ///< keep: the kept positions; exchange: received row of each point after
  std::vector<int> send_order_, send_counts_;  ///< exchange: this rank's points by destination, and how many to each
  std::vector<int> ids_;                       ///< exchange: the ids after
  ranks::Neighbours neighbours_;               ///< exchange: the ranks sent to and received from
};

}  // namespace gradmpm
