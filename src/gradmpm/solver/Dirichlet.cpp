#include "gradmpm/solver/Dirichlet.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace gradmpm {

void DirichletElimination::apply_to_matrix(SparseMatrix& A, const std::vector<int>& dofs) {
  dofs_ = dofs;
  removed_.clear();
  std::vector<int> index(A.rows(), -1);  // constraint number of each dof, or -1
  for (std::size_t k = 0; k < dofs.size(); ++k) {
    if (dofs[k] < 0 || dofs[k] >= A.rows()) throw std::out_of_range("Dirichlet constraint on a dof outside the system");
    index[dofs[k]] = static_cast<int>(k);
  }
  // Constrained equations get the largest diagonal of A: the scale of the system, so the
  // factorisation sees no tiny or negative pivot there whatever the row held before.
  double scale = 0.0;
  const int* inner = A.innerIndexPtr();
  for (int col = 0; col < A.outerSize(); ++col) {  // the diagonal by binary search in each column
    const int* begin = inner + A.outerIndexPtr()[col];
    const int* end =
        inner + (A.isCompressed() ? A.outerIndexPtr()[col + 1] : A.outerIndexPtr()[col] + A.innerNonZeroPtr()[col]);
    const int* d = std::lower_bound(begin, end, col);
    if (d != end && *d == col) scale = std::max(scale, std::abs(A.valuePtr()[d - inner]));
  }
  if (!(scale > 0.0)) scale = 1.0;
  scale_ = scale;
  for (int col = 0; col < A.outerSize(); ++col) {
    for (SparseMatrix::InnerIterator it(A, col); it; ++it) {
      const int row = it.row();
      const int kc = index[col], kr = index[row];
      if (kc < 0 && kr < 0) continue;
      if (row == col) {
        it.valueRef() = scale;
        continue;
      }
      if (kc >= 0 && kr < 0) removed_.push_back({row, kc, it.value()});
      it.valueRef() = 0.0;
    }
  }
}

void DirichletElimination::apply_to_rhs(Vector& b, const std::vector<double>& values) const {
  if (values.size() != dofs_.size()) throw std::invalid_argument("Dirichlet values do not match the constrained dofs");
  for (const Entry& e : removed_) b[e.row] -= e.value * values[e.constraint];
  for (std::size_t k = 0; k < dofs_.size(); ++k) b[dofs_[k]] = scale_ * values[k];
}

}  // namespace gradmpm
