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
// A rank's vectors are in its local numbering (DofMap: its own rows first, then the
// others it knows, by increasing global row; grid partition step 2b, docs/parallel.md):
// `globals` maps its rows to the global rows PETSc and the owners know. Without it the
// local rows are the global ones (vectors as long as the whole system).
#include <algorithm>
#include <array>
#include <cmath>
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

  /// `rank_rows`: rank r owns global rows [rank_rows[r], rank_rows[r + 1]) (DofMap::rank_rows;
  /// empty: serial). `touched`: the local rows this rank's points read or add to, ascending
  /// (own rows among them are ignored). `globals`: the global row of each local row
  /// (DofMap::global_rows; this rank's own rows a run of local rows, the others ascending
  /// in global row); empty: local rows are global. A collective call.
  RowHalo(std::vector<int> rank_rows, const std::vector<int>& touched, std::vector<int> globals = {})
      : rank_rows_(std::move(rank_rows)), globals_(std::move(globals)) {
    if (rank_rows_.empty()) return;
    if (static_cast<int>(rank_rows_.size()) != ranks::size() + 1)
      throw std::logic_error("RowHalo: rows by rank need one more entry than there are ranks");
    const int me = ranks::rank();
    const int global_first = rank_rows_[me], own = rank_rows_[me + 1] - global_first;
    first_ = global_first;
    if (!globals_.empty()) {  // the own rows' run of local rows
      const auto at = std::find(globals_.begin(), globals_.end(), global_first);
      first_ = own > 0 ? static_cast<int>(at - globals_.begin()) : 0;
      for (int k = 0; k < own; ++k)
        if (first_ + k >= static_cast<int>(globals_.size()) || globals_[first_ + k] != global_first + k)
          throw std::logic_error("RowHalo: this rank's own rows are not a run of its local rows");
    }
    last_ = first_ + own;
    std::vector<std::vector<int>> to(ranks::size());
    for (const int row : touched) {
      if (row >= first_ && row < last_) continue;
      const int g = global_row(row);
      if (!ghosts_.empty() && g <= global_row(ghosts_.back()))
        throw std::logic_error("RowHalo: ghost rows must ascend in global row");
      ghosts_.push_back(row);  // ascending global rows: grouped by owner in rank order
      to[owner(g)].push_back(g);
    }
    if (!to[me].empty()) throw std::logic_error("RowHalo: a ghost row in this rank's own range");
    const ranks::Sent<int> asked = ranks::send_to(to);
    to_owners_ = asked.with;
    requested_ = asked.received;
    for (int& row : requested_) {
      if (row < global_first || row >= global_first + own)
        throw std::logic_error("RowHalo: a rank asked for a row this rank does not own");
      row = first_ + (row - global_first);  // its local row
    }
    to_ghosts_ = to_owners_.reversed();
  }

  bool distributed() const { return !rank_rows_.empty(); }
  /// This rank's rows: local rows [first(), last()) (every row serially: last() is not
  /// known then), global rows [rank_rows()[rank], rank_rows()[rank + 1]).
  int first() const { return distributed() ? first_ : 0; }
  int last() const { return distributed() ? last_ : -1; }
  /// The global row of local row `row`.
  int global_row(int row) const { return globals_.empty() ? row : globals_[row]; }
  /// Whether local rows are global ones (a serial run, or vectors as long as the system).
  bool local_is_global() const { return globals_.empty(); }
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
  std::vector<int> globals_;    ///< local row -> global row (empty: the same)
  int first_ = 0, last_ = 0;    ///< this rank's own local rows
  std::vector<int> ghosts_;     ///< local rows this rank holds but others own, ascending in global row
  std::vector<int> requested_;  ///< own local rows other ranks hold, grouped by that rank in rank order
  ranks::Neighbours to_owners_, to_ghosts_;
};

}  // namespace gradmpm
