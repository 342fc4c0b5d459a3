#pragma once
// Prescribed values u_c = g_c by symmetric elimination that keeps the sparsity
// pattern (and so CHOLMOD's symbolic analysis): rows and columns of constrained dofs
// are zeroed, their diagonal set to s = max_i |A_ii| (the scale of the system), and the
// removed column entries remembered so that every right-hand side can be lifted:
// b_i -= A_ic g_c, b_c = s g_c.
#include <vector>

#include "gradmpm/core/Types.hpp"
#include "gradmpm/solver/RowHalo.hpp"

namespace gradmpm {

class DirichletElimination {
 public:
  /// Eliminates `dofs` from A in place. A keeps its pattern and stays SPD. `halo`: a
  /// distributed run's rows (RowHalo), A being this rank's share of the matrix (the
  /// ranks' shares add up to it): the scale is the summed matrix's, the share of each
  /// constrained row's owner holds its diagonal (its pattern must have it), and the lift
  /// of a right-hand side is summed in own and ghost rows. Null or serial: A is whole.
  ///
  /// `symmetric_pattern`: A's pattern is structurally symmetric (every pattern
  /// build_pattern_of_groups makes is: unions of the points' node cliques). The entries of
  /// constrained rows are then found through the constrained columns' entries, by a search
  /// in each column they name, instead of a pass over all of A (serial, 3e6 entries at 1e5
  /// dof in 2D, at every Newton iteration). The result is the same bit for bit. A pattern
  /// that is not symmetric is an error (std::logic_error) where it shows: a constrained
  /// column's entry with no transposed entry.
  void apply_to_matrix(SparseMatrix& A, const std::vector<int>& dofs, const RowHalo* halo = nullptr,
                       bool symmetric_pattern = false);

  /// Lifts b for the prescribed `values` (same order as the dofs given above); with a
  /// halo, b is lifted in this rank's own and ghost rows.
  void apply_to_rhs(Vector& b, const std::vector<double>& values) const;

  /// x_c = g_c exactly: a Krylov solver meets the constrained equations only to its
  /// tolerance, and an error left there would never be corrected (the residual skips
  /// the constrained dofs), so a solution is made exact on them.
  void impose(Vector& x, const std::vector<double>& values) const {
    for (std::size_t k = 0; k < dofs_.size(); ++k) x[dofs_[k]] = values[k];
  }

  const std::vector<int>& dofs() const { return dofs_; }

 private:
  struct Entry {
    int row, constraint;
    double value;
  };
  std::vector<int> dofs_;
  double scale_ = 1.0;          ///< the diagonal given to constrained equations
  const RowHalo* halo_ = nullptr;  ///< A was a rank's share of a distributed run's matrix
  std::vector<Entry> removed_;  ///< A_ic for free rows i and constrained columns c
};

}  // namespace gradmpm
