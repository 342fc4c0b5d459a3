#include "gradmpm/solver/Dirichlet.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "gradmpm/core/Parallel.hpp"
#include "gradmpm/core/Ranks.hpp"

namespace gradmpm {

namespace {
/// The entries of column `col` of A: [begin, end) of its inner indices (compressed or not).
std::pair<const int*, const int*> column_rows(const SparseMatrix& A, int col) {
  const int* inner = A.innerIndexPtr();
  const int first = A.outerIndexPtr()[col];
  const int last = A.isCompressed() ? A.outerIndexPtr()[col + 1] : first + A.innerNonZeroPtr()[col];
  return {inner + first, inner + last};
}
}  // namespace

void DirichletElimination::apply_to_matrix(SparseMatrix& A, const std::vector<int>& dofs, const RowHalo* halo,
                                           bool symmetric_pattern) {
  dofs_ = dofs;
  halo_ = halo && halo->distributed() ? halo : nullptr;
  removed_.clear();
  std::vector<int> index(A.rows(), -1);  // constraint number of each dof, or -1
  for (std::size_t k = 0; k < dofs.size(); ++k) {
    if (dofs[k] < 0 || dofs[k] >= A.rows()) throw std::out_of_range("Dirichlet constraint on a dof outside the system");
    index[dofs[k]] = static_cast<int>(k);
  }
  // Constrained equations get the largest diagonal of A: the scale of the system, so the
  // factorisation sees no tiny or negative pivot there whatever the row held before.
  Vector diagonal = Vector::Zero(A.rows());
  const int* inner = A.innerIndexPtr();
  const int columns = static_cast<int>(A.outerSize());
#pragma omp parallel for schedule(static) if (use_threads(columns))
  for (int col = 0; col < columns; ++col) {  // the diagonal by binary search in each column
    const auto [begin, end] = column_rows(A, col);
    const int* d = std::lower_bound(begin, end, col);
    if (d != end && *d == col) diagonal[col] = A.valuePtr()[d - inner];
  }
  double scale = 0.0;
  if (halo_) {  // the summed diagonal in this rank's own rows, then the largest over the ranks
    halo_->add_to_owners(diagonal);
    const Eigen::Index own = halo_->last() - halo_->first();
    if (own > 0) scale = diagonal.segment(halo_->first(), own).cwiseAbs().maxCoeff();
    ranks::max(&scale, 1);
  } else if (diagonal.size() > 0) {
    scale = diagonal.cwiseAbs().maxCoeff();
  }
  if (!(scale > 0.0)) scale = 1.0;
  scale_ = scale;
  // Column col's entries at rows that are constrained or in a constrained column: zeroed,
  // the diagonal set to the scale, the constrained columns' free-row entries remembered.
  auto eliminate = [&](int col, const int* begin, const int* end) {
    double* values = A.valuePtr();
    for (const int* at = begin; at != end; ++at) {
      const int row = *at;
      const int kc = index[col], kr = index[row];
      if (kc < 0 && kr < 0) continue;
      double& value = values[at - inner];
      if (row == col) {
        const bool mine = !halo_ || (row >= halo_->first() && row < halo_->last());  // in one share only
        value = mine ? scale : 0.0;
        continue;
      }
      if (kc >= 0 && kr < 0) removed_.push_back({row, kc, value});
      value = 0.0;
    }
  };
  if (!symmetric_pattern) {
    for (int col = 0; col < columns; ++col) {
      const auto [begin, end] = column_rows(A, col);
      eliminate(col, begin, end);
    }
    return;
  }
  // Symmetric pattern: constrained columns in ascending order (removed_ as the pass over
  // all columns lists it); a free column holds entries of constrained rows only where a
  // constrained column holds its transpose, each found by binary search.
  std::vector<int> constrained = dofs;
  std::sort(constrained.begin(), constrained.end());
  constrained.erase(std::unique(constrained.begin(), constrained.end()), constrained.end());
  for (const int col : constrained) {
    const auto [begin, end] = column_rows(A, col);
    for (const int* at = begin; at != end; ++at) {
      if (index[*at] >= 0) continue;  // a constrained column: met in its own turn
      const auto [first, last] = column_rows(A, *at);
      const int* t = std::lower_bound(first, last, col);
      if (t == last || *t != col)
        throw std::logic_error("Dirichlet elimination: the matrix's pattern is not symmetric as its caller declared");
      A.valuePtr()[t - inner] = 0.0;
    }
    eliminate(col, begin, end);
  }
}

void DirichletElimination::apply_to_rhs(Vector& b, const std::vector<double>& values) const {
  if (values.size() != dofs_.size()) throw std::invalid_argument("Dirichlet values do not match the constrained dofs");
  if (halo_) {  // each rank's share of A_ic g_c, summed in own and ghost rows; always (the
    // values may differ between ranks outside their rows, so no rank skips the exchange)
    Vector lift = Vector::Zero(b.size());
    for (const Entry& e : removed_) lift[e.row] += e.value * values[e.constraint];
    halo_->sum(lift);
    b -= lift;
  } else {
    for (const Entry& e : removed_) b[e.row] -= e.value * values[e.constraint];
  }
  for (std::size_t k = 0; k < dofs_.size(); ++k) b[dofs_[k]] = scale_ * values[k];
}

}  // namespace gradmpm
