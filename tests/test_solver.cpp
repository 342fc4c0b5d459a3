// Requirements on the sparse machinery: the pattern + scatter-add assembly gives the
// same operator as a dense reference, Dirichlet elimination gives the constrained
// solution, CHOLMOD and Eigen agree, and an indefinite matrix is reported, not solved.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "gradmpm/basis/LinearBasis.hpp"
#include "gradmpm/core/Errors.hpp"
#include "gradmpm/points/Generate.hpp"
#include "gradmpm/solver/Assembler.hpp"
#include "gradmpm/solver/Dirichlet.hpp"
#include "gradmpm/solver/SpdSolver.hpp"

using namespace gradmpm;

namespace {
struct Setup2D {
  Grid<2> grid{Vec<2>(0.0, 0.0), Vec<2>(0.5, 0.5), {3, 2}};
  MaterialPoints<2> points;
  PointStencils<2> st;
  DofMap dofs;
  Setup2D() {
    // Points in two cells only: nodes of the third column stay inactive.
    add_gauss_points<2>(grid, {0, 0}, {2, 2}, 2, [](const Vec<2>&) { return 0; }, points);
    st = evaluate_stencils<2, LinearBasis<2>>(grid, points);
    dofs = DofMap(st, grid.num_nodes(), 1);
  }
};
}  // namespace

TEST(Assembler, OnlyNodesTouchedByPointsAreActive) {
  Setup2D s;
  EXPECT_EQ(s.grid.num_nodes(), 12);
  EXPECT_EQ(s.dofs.num_active_nodes(), 9);
}

TEST(Assembler, ScatterAddMatchesDenseReference) {
  Setup2D s;
  SparseMatrix M = build_pattern(s.st, s.dofs);
  const SparseMatrix pattern = M;
  Assembler<2> as(s.st, s.points, s.dofs);
  as.add_mass(M);
  SparseMatrix L = pattern;
  as.add_laplacian(L);

  const int n = s.dofs.num_dofs();
  Eigen::MatrixXd Md = Eigen::MatrixXd::Zero(n, n), Ld = Eigen::MatrixXd::Zero(n, n);
  for (int p = 0; p < s.points.size(); ++p)
    for (int a = 0; a < s.st[p].count; ++a)
      for (int b = 0; b < s.st[p].count; ++b) {
        const int i = s.dofs.dof(s.st[p].node[a], 0), j = s.dofs.dof(s.st[p].node[b], 0);
        Md(i, j) += s.st[p].N[a] * s.st[p].N[b] * s.points.volume[p];
        Ld(i, j) += s.st[p].dN[a].dot(s.st[p].dN[b]) * s.points.volume[p];
      }
  EXPECT_LT((Eigen::MatrixXd(M) - Md).norm(), 1e-14);
  EXPECT_LT((Eigen::MatrixXd(L) - Ld).norm(), 1e-13);
  EXPECT_NEAR(Md.sum(), 1.0, 1e-14) << "sum of M = area covered by the points (1.0 x 1.0)";
  EXPECT_LT((Ld * Eigen::VectorXd::Ones(n)).norm(), 1e-13) << "L annihilates constants";
}

TEST(Dirichlet, EliminationGivesConstrainedSolution) {
  // Small SPD system; compare with solving the free block directly.
  Eigen::MatrixXd A(4, 4);
  A << 4, -1, 0, -1, -1, 4, -1, 0, 0, -1, 4, -1, -1, 0, -1, 4;
  Eigen::VectorXd b(4);
  b << 1, 2, 3, 4;
  SparseMatrix As = A.sparseView();
  DirichletElimination bc;
  bc.apply_to_matrix(As, {1, 3});
  Vector rhs = b;
  bc.apply_to_rhs(rhs, {0.5, -2.0});
  SpdSolver solver;
  solver.compute(As);
  const Vector x = solver.solve(rhs);
  EXPECT_NEAR(x[1], 0.5, 1e-14);
  EXPECT_NEAR(x[3], -2.0, 1e-14);
  // free equations: rows 0 and 2 of A x = b
  EXPECT_NEAR(A.row(0).dot(x), b[0], 1e-13);
  EXPECT_NEAR(A.row(2).dot(x), b[2], 1e-13);
}

TEST(SpdSolver, CholmodAndEigenAgreeAndAnalysisIsReused) {
  const int n = 200;
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 2.0 + 0.01 * i);
    if (i + 1 < n) {
      t.emplace_back(i, i + 1, -1.0);
      t.emplace_back(i + 1, i, -1.0);
    }
  }
  SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  const Vector b = Vector::LinSpaced(n, -1.0, 1.0);
  SpdSolver chol(SpdSolver::Backend::Cholmod), ldlt(SpdSolver::Backend::EigenLDLT);
  chol.compute(A);
  ldlt.compute(A);
  const Vector x1 = chol.solve(b);
  EXPECT_LT((A * x1 - b).norm(), 1e-12 * b.norm());
  EXPECT_LT((x1 - ldlt.solve(b)).norm(), 1e-12 * x1.norm());
  // New values, same pattern: factorize() alone must be enough.
  SparseMatrix A2 = A * 3.0;
  chol.factorize(A2);
  EXPECT_LT((chol.solve(b) - x1 / 3.0).norm(), 1e-12 * x1.norm());
}

TEST(SpdSolver, PreconditionedCgSolvesAndReportsFailure) {
  // 2D five-point Laplacian (+ a small shift): incomplete Cholesky is not exact here.
  const int m = 30, n = m * m;
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) {
      const int k = i * m + j;
      t.emplace_back(k, k, 4.0 + 1e-3);
      if (i + 1 < m) {
        t.emplace_back(k, k + m, -1.0);
        t.emplace_back(k + m, k, -1.0);
      }
      if (j + 1 < m) {
        t.emplace_back(k, k + 1, -1.0);
        t.emplace_back(k + 1, k, -1.0);
      }
    }
  SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  const Vector b = Vector::LinSpaced(n, -1.0, 1.0);
  SpdSolver chol, pcg(SpdSolver::Backend::PCG);
  chol.compute(A);
  pcg.compute(A);
  const Vector x = chol.solve(b);
  EXPECT_LT((pcg.solve(b) - x).norm(), 1e-8 * x.norm());
  SpdSolver limited(SpdSolver::Backend::PCG);
  limited.pcg_max_iterations = 2;
  limited.pcg_tolerance = 1e-14;
  limited.compute(A);
  try {
    limited.solve(b);
    FAIL() << "expected SolverError";
  } catch (const SolverError& e) {
    EXPECT_NE(std::string(e.what()).find("preconditioned CG did not converge"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("after 2 iterations"), std::string::npos) << e.what();
  }
}

TEST(SpdSolver, IndefiniteMatrixIsReported) {
  SparseMatrix A(2, 2);
  A.insert(0, 0) = 1.0;
  A.insert(1, 1) = -1.0;
  for (auto backend : {SpdSolver::Backend::Cholmod, SpdSolver::Backend::EigenLDLT}) {  // PCG: see above
    SpdSolver s(backend);
    EXPECT_THROW(s.compute(A), SolverError) << SpdSolver::name(backend);
  }
}
