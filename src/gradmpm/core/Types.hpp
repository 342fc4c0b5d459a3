#pragma once
// Basic vocabulary shared by every module: fixed-size vectors per dimension and
// the sparse matrix type that all global operators (stiffness, M, L) use.
#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace gradmpm {

template <int dim>
using Vec = Eigen::Matrix<double, dim, 1>;

/// Column-major (CSC) sparse matrix: the layout CHOLMOD consumes directly.
using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using Vector = Eigen::VectorXd;

constexpr int ipow(int base, int exp) { return exp == 0 ? 1 : base * ipow(base, exp - 1); }

}  // namespace gradmpm
