#include "gradmpm/solver/Dirichlet.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "gradmpm/core/Ranks.hpp"

namespace gradmpm {

void DirichletElimination::apply_to_matrix(SparseMatrix& A, const std::vector<int>& dofs, const RowHalo* halo) {
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
  for (int col = 0; col < A.outerSize(); ++col) {  // the diagonal by binary search in each column
    const int* begin = inner + A.outerIndexPtr()[col];
    const int* end =
        inner + (A.isCompressed() ? A.outerIndexPtr()[col + 1] : A.outerIndexPtr()[col] + A.innerNonZeroPtr()[col]);
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
  for (int col = 0; col < A.outerSize(); ++col) {
    for (SparseMatrix::InnerIterator it(A, col); it; ++it) {
      const int row = it.row();
      const int kc = index[col], kr = index[row];
      if (kc < 0 && kr < 0) continue;
      if (row == col) {
        const bool mine = !halo_ || (row >= halo_->first() && row < halo_->last());  // in one share only
        it.valueRef() = mine ? scale : 0.0;
        continue;
      }
      if (kc >= 0 && kr < 0) removed_.push_back({row, kc, it.value()});
      it.valueRef() = 0.0;
    }
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
