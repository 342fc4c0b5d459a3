#pragma once
// A distributed run's vectors in equation numbering (f_int, the residual, the Newton
// increment): rank r owns the rows DofMap::rank_rows gives it (the active nodes of its
// cells), and its points also read and add to a few rows of its neighbours (its ghost
// rows: the nodes its points' supports reach across the cut). The Newton iteration needs
// each vector right only in the rows a rank owns or reads, so instead of summing or
// gathering the whole vector over the ranks (an all-reduce of every equation, each
// iteration), the ghost rows' values travel between neighbours only:
//   add_to_owners: each rank's partial sums in its ghost rows are added at their owners;
//   fetch_ghosts:  each rank's ghost rows get their owners' values.
// The neighbours are found once per load step (ranks::neighbours_of, no all-to-all).
// Serially there are no ghost rows and every operation is the identity.
// (Grid partition, step 2 in docs/parallel.md: the vectors are still as long as the
// active grid; what a rank holds outside its own and ghost rows is not used.)
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/core/Types.hpp"

namespace gradmpm {

/// The rows of the nodes a pattern couples (its columns with entries; a pattern of point
/// stencils couples each node with itself), ascending: what a rank's share touches.
inline std::vector<int> touched_rows(const SparseMatrix& pattern) {
  std::vector<int> rows;
  const auto* outer = pattern.outerIndexPtr();
  for (int c = 0; c < pattern.outerSize(); ++c)
    if ((pattern.isCompressed() ? outer[c + 1] - outer[c] : pattern.innerNonZeroPtr()[c]) > 0) rows.push_back(c);
  return rows;
}

class RowHalo {
 public:
  /// A serial run's: every row is this rank's.
  RowHalo() = default;

  /// `rank_rows`: rank r owns rows [rank_rows[r], rank_rows[r + 1]) (DofMap::rank_rows;
  /// empty: serial). `touched`: the rows this rank's points read or add to, ascending
  /// (own rows among them are ignored). A collective call.
  RowHalo(std::vector<int> rank_rows, const std::vector<int>& touched) : rank_rows_(std::move(rank_rows)) {
    if (rank_rows_.empty()) return;
    if (static_cast<int>(rank_rows_.size()) != ranks::size() + 1)
      throw std::logic_error("RowHalo: rows by rank need one more entry than there are ranks");
    const int me = ranks::rank();
    std::vector<long long> count(ranks::size(), 0);
    for (const int row : touched) {
      if (row >= first() && row < last()) continue;
      ghosts_.push_back(row);  // ascending rows: grouped by owner in rank order
      ++count[owner(row)];
    }
    count[me] = 0;
    to_owners_ = ranks::neighbours_of(count);
    const std::vector<char> asked = ranks::exchange(to_owners_, reinterpret_cast<const char*>(ghosts_.data()), sizeof(int));
    requested_.resize(asked.size() / sizeof(int));
    if (!asked.empty()) std::memcpy(requested_.data(), asked.data(), asked.size());
    for (const int row : requested_)
      if (row < first() || row >= last()) throw std::logic_error("RowHalo: a rank asked for a row this rank does not own");
    to_ghosts_ = to_owners_.reversed();
  }

  bool distributed() const { return !rank_rows_.empty(); }
  /// This rank's rows: [first(), last()) (every row serially: last() is not known then).
  int first() const { return distributed() ? rank_rows_[ranks::rank()] : 0; }
  int last() const { return distributed() ? rank_rows_[ranks::rank() + 1] : -1; }
  const std::vector<int>& rank_rows() const { return rank_rows_; }
  /// Rows this rank holds for its points but does not own, and rows of its own that
  /// other ranks hold (the values sent each way per exchange).
  std::size_t ghost_rows() const { return ghosts_.size(); }
  std::size_t shared_rows() const { return requested_.size(); }

  /// The owners' rows get the sum over the ranks (their own value plus the ghosts' in
  /// rank order: the same bits however the messages arrive); ghost rows keep this
  /// rank's part.
  void add_to_owners(Eigen::Ref<Vector> v) const { send(v.data(), v.size(), 1, ghosts_, to_owners_, requested_, add); }

  /// Ghost rows get their owners' values.
  void fetch_ghosts(Eigen::Ref<Vector> v) const { send(v.data(), v.size(), 1, requested_, to_ghosts_, ghosts_, put); }

  /// The sum over the ranks of each rank's partial vector, right in this rank's own and
  /// ghost rows (what a whole-vector sum gave, where it is read).
  void sum(Eigen::Ref<Vector> v) const {
    add_to_owners(v);
    fetch_ghosts(v);
  }

  /// The same for every column of V at once (several fields or right-hand sides: one
  /// message to each neighbour, not one per column; the same bits as column by column).
  void fetch_ghosts(Eigen::MatrixXd& V) const { send(V.data(), V.rows(), V.cols(), requested_, to_ghosts_, ghosts_, put); }
  void sum(Eigen::MatrixXd& V) const {
    send(V.data(), V.rows(), V.cols(), ghosts_, to_owners_, requested_, add);
    fetch_ghosts(V);
  }

  /// The 2-norms of vectors that are right in every rank's own rows, with one reduction
  /// (the same bits on every rank; serially Eigen's norms).
  template <std::size_t n>
  std::array<double, n> norms(const std::array<const Vector*, n>& v) const {
    std::array<double, n> result{};
    if (!distributed()) {
      for (std::size_t k = 0; k < n; ++k) result[k] = v[k]->norm();
      return result;
    }
    for (std::size_t k = 0; k < n; ++k) result[k] = v[k]->segment(first(), last() - first()).squaredNorm();
    ranks::sum(result.data(), n);
    for (double& x : result) x = std::sqrt(x);
    return result;
  }

 private:
  static void add(double& row, double value) { row += value; }
  static void put(double& row, double value) { row = value; }

  /// The rows `from` of the `cols` columns of v (column-major, `ld` rows) to the
  /// neighbours `to` (grouped as they expect), where each received row is put into v's
  /// row of `into` by `apply`.
  void send(double* v, Eigen::Index ld, Eigen::Index cols, const std::vector<int>& from, const ranks::Neighbours& to,
            const std::vector<int>& into, void (*apply)(double&, double)) const {
    if (!distributed()) return;
    std::vector<double> values(from.size() * cols);
    for (std::size_t k = 0; k < from.size(); ++k)
      for (Eigen::Index j = 0; j < cols; ++j) values[k * cols + j] = v[from[k] + j * ld];
    const std::vector<char> got = ranks::exchange(to, reinterpret_cast<const char*>(values.data()), cols * sizeof(double));
    const double* value = reinterpret_cast<const double*>(got.data());
    for (std::size_t k = 0; k < into.size(); ++k)
      for (Eigen::Index j = 0; j < cols; ++j) apply(v[into[k] + j * ld], value[k * cols + j]);
  }

  int owner(int row) const {
    return static_cast<int>(std::upper_bound(rank_rows_.begin(), rank_rows_.end(), row) - rank_rows_.begin()) - 1;
  }

  std::vector<int> rank_rows_;
  std::vector<int> ghosts_;     ///< rows this rank holds but others own, ascending
  std::vector<int> requested_;  ///< own rows other ranks hold, grouped by that rank in rank order
  ranks::Neighbours to_owners_, to_ghosts_;
};

}  // namespace gradmpm
