// Requirements on the sparse machinery: the pattern + scatter-add assembly gives the same
// operator as a dense reference, Dirichlet elimination gives the constrained solution
// (and, on a symmetric pattern, the same matrix bit for bit whether it passes over every
// column or searches through the constrained ones), every registered linear solver (one
// interface, created by name) solves what it claims to: the SPD ones agree and refuse an
// indefinite matrix, the general ones solve a non-symmetric system without symmetrising
// it, a symmetric-only choice hands non-symmetric matrices to linear_solver.general, and a
// solver defined only in this test joins the registry with one call (recipe "add a linear
// solver"), CHOLMOD takes another solver's ordering when told (order_like), keeps an
// ordering it is asked to compare only where its factor is cheaper, and spends less on the
// ordering of a system factorised once, factorises again on its analysis after its factor
// was released, and CHOLMOD leaves the caller's OpenMP settings as
// they were (its serial regions as plain calls: test_tuning.cpp).
#include <gtest/gtest.h>

#include <omp.h>

#include <Eigen/CholmodSupport>
#include <Eigen/Dense>

#include <cmath>

#include "SolverTestUtil.hpp"
#include "gradmpm/basis/LinearBasis.hpp"
#include "gradmpm/core/Errors.hpp"
#include "gradmpm/points/Generate.hpp"
#include "gradmpm/solver/Assembler.hpp"
#include "gradmpm/solver/Dirichlet.hpp"
#include "gradmpm/solver/linear/LinearSolver.hpp"

using namespace gradmpm;

namespace {
struct Setup2D {
  Grid<2> grid{Vec<2>(0.0, 0.0), Vec<2>(0.5, 0.5), {3, 2}};
  MaterialPoints<2> points;
  PointStencils<2> st;
  DofMap dofs;
  Setup2D() {
    // Points in two cells only: nodes of the third column stay inactive.
    add_gauss_points<2>(
        grid, {0, 0}, {2, 2}, 2, [](const Vec<2>&) { return 0; }, points);
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
  const auto solver = make_linear_solver({});
  solver->compute(As);
  const Vector x = solver->solve(rhs);
  EXPECT_NEAR(x[1], 0.5, 1e-14);
  EXPECT_NEAR(x[3], -2.0, 1e-14);
  // free equations: rows 0 and 2 of A x = b
  EXPECT_NEAR(A.row(0).dot(x), b[0], 1e-13);
  EXPECT_NEAR(A.row(2).dot(x), b[2], 1e-13);
}

TEST(Dirichlet, ASymmetricPatternIsEliminatedThroughTheConstrainedColumnsBitForBit) {
  // A 2D pattern of node cliques (build_pattern, two components) with values that are not
  // symmetric, constrained dofs given unsorted, two of them in one node (a constrained row
  // in a constrained column): the search through the constrained columns leaves the matrix
  // and the lifted right-hand side exactly as the pass over every column does.
  Grid<2> grid{Vec<2>(0.0, 0.0), Vec<2>(0.25, 0.25), {4, 4}};
  MaterialPoints<2> points;
  add_gauss_points<2>(
      grid, {0, 0}, {4, 4}, 2, [](const Vec<2>&) { return 0; }, points);
  const PointStencils<2> st = evaluate_stencils<2, LinearBasis<2>>(grid, points);
  const DofMap dofs(st, grid.num_nodes(), 2);
  SparseMatrix A = build_pattern(st, dofs);
  for (int col = 0; col < A.outerSize(); ++col)
    for (SparseMatrix::InnerIterator it(A, col); it; ++it)
      it.valueRef() = (it.row() == col ? 10.0 : 0.0) + std::sin(1.0 + 3.0 * it.row() + 0.7 * col);
  const std::vector<int> constrained{dofs.dof(7, 1), dofs.dof(0, 0), dofs.dof(0, 1), dofs.dof(13, 0)};
  const std::vector<double> values{0.25, -1.0, 0.5, 2.0};
  SparseMatrix full = A, searched = A;
  DirichletElimination by_pass, by_search;
  by_pass.apply_to_matrix(full, constrained);
  by_search.apply_to_matrix(searched, constrained, nullptr, true);
  Vector b_pass = Vector::LinSpaced(A.rows(), -1.0, 2.0), b_search = b_pass;
  by_pass.apply_to_rhs(b_pass, values);
  by_search.apply_to_rhs(b_search, values);
  ASSERT_EQ(full.nonZeros(), searched.nonZeros());
  int zeroed = 0;
  for (Eigen::Index k = 0; k < full.nonZeros(); ++k) {
    EXPECT_EQ(full.valuePtr()[k], searched.valuePtr()[k]) << "entry " << k;
    zeroed += full.valuePtr()[k] == 0.0;
  }
  EXPECT_GT(zeroed, 30) << "the constrained rows and columns were zeroed";
  for (Eigen::Index i = 0; i < b_pass.size(); ++i) EXPECT_EQ(b_pass[i], b_search[i]) << "row " << i;
  // A pattern that is not symmetric, where a constrained column shows it, is refused.
  SparseMatrix lower =
      SparseMatrix(Eigen::MatrixXd::Ones(4, 4).triangularView<Eigen::Lower>().toDenseMatrix().sparseView());
  DirichletElimination refused;
  EXPECT_THROW(refused.apply_to_matrix(lower, {1}, nullptr, true), std::logic_error);
}

namespace {
SparseMatrix tridiagonal(int n, double lower, double upper) {
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 2.0 + 0.01 * i);
    if (i + 1 < n) {
      t.emplace_back(i, i + 1, upper);
      t.emplace_back(i + 1, i, lower);
    }
  }
  SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}
LinearSolverSettings named(const std::string& type) {
  LinearSolverSettings s;
  s.type = type;
  return s;
}
}  // namespace

TEST(LinearSolver, EverySolverAgreesOnAnSpdSystemAndReusesItsAnalysis) {
  const SparseMatrix A = tridiagonal(200, -1.0, -1.0);
  const Vector b = Vector::LinSpaced(200, -1.0, 1.0);
  const auto ref = make_linear_solver(named("cholmod"));
  ref->compute(A);
  const Vector x1 = ref->solve(b);
  EXPECT_LT((A * x1 - b).norm(), 1e-12 * b.norm());
  for (const auto& info : LinearSolverRegistry::instance().all()) {
    const auto s = make_linear_solver(named(info.name));
    EXPECT_EQ(s->name(), info.name);
    s->compute(A);
    EXPECT_LT((s->solve(b) - x1).norm(), 1e-10 * x1.norm()) << info.name;
    // New values, same pattern: factorize() alone must be enough.
    s->factorize(SparseMatrix(A * 3.0));
    EXPECT_LT((s->solve(b) - x1 / 3.0).norm(), 1e-10 * x1.norm()) << info.name;
    // Several right-hand sides at once give the single solves.
    Eigen::MatrixXd B(200, 2);
    B << b, 2.0 * b;
    const Eigen::MatrixXd X = s->solve(B);
    EXPECT_LT((X.col(1) - 2.0 * x1 / 3.0).norm(), 1e-10 * x1.norm()) << info.name;
  }
}

// gradmpm calls CHOLMOD's supernodal factorisation directly on tril(P A P'), formed once
// per analysis with each entry's source in A (solver/linear/Cholmod.cpp), where
// cholmod_factorize transposes A at every call. Same matrix, same factor: the solutions
// equal cholmod_factorize's (through Eigen's wrapper) bit for bit, after new values
// with the same pattern too (the gather refilled), and from a matrix given uncompressed.
TEST(LinearSolver, CholmodGivesCholmodFactorizesAnswerBitForBit) {
  SparseMatrix A = test::laplacian_2d(30);
  for (int k = 0; k < A.outerSize(); ++k)  // unequal values, still symmetric
    for (SparseMatrix::InnerIterator it(A, k); it; ++it)
      it.valueRef() *= 1.0 + 0.1 * std::sin(double(it.row() + it.col()));
  const Vector b = Vector::LinSpaced(A.rows(), -1.0, 2.0);
  const auto ours = make_linear_solver(named("cholmod"));
  Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Upper> reference;
  for (const double scale : {1.0, 2.5}) {
    const SparseMatrix As = A * scale;
    if (scale == 1.0) {
      ours->compute(As);
      reference.compute(As);
    } else {
      ours->factorize(As);
      reference.factorize(As);
    }
    ASSERT_EQ(reference.info(), Eigen::Success);
    const Vector x = ours->solve(b), y = reference.solve(b);
    EXPECT_EQ((x - y).lpNorm<Eigen::Infinity>(), 0.0) << "scale " << scale;
    EXPECT_LT((As * x - b).norm(), 1e-12 * b.norm());
  }
  SparseMatrix uncompressed = A;
  uncompressed.uncompress();
  ASSERT_FALSE(uncompressed.isCompressed());
  const auto fresh = make_linear_solver(named("cholmod"));
  fresh->compute(uncompressed);
  reference.compute(A);
  EXPECT_EQ((fresh->solve(b) - reference.solve(b)).lpNorm<Eigen::Infinity>(), 0.0);
}

// The gradient step's smoothers of one pattern share one ordering (LinearSolver::
// order_like, MpmGradient.cpp): a CHOLMOD solver told to take another's ordering analyses
// with it. On the same pattern with other values it gives the answer of its own analysis
// bit for bit (the same ordering); on another pattern it still solves, with the fill of
// the ordering it was given: a star whose hub comes early fills in, where its own
// ordering (the hub last) would not.
TEST(LinearSolver, CholmodTakesAnotherSolversOrdering) {
  const SparseMatrix A = test::laplacian_2d(30);
  SparseMatrix B = A;  // other values, one pattern
  for (int k = 0; k < B.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(B, k); it; ++it)
      it.valueRef() *= 1.0 + 0.1 * std::sin(double(it.row() + it.col()));
  const Vector b = Vector::LinSpaced(A.rows(), -1.0, 2.0);
  const auto first = make_linear_solver(named("cholmod")), taken = make_linear_solver(named("cholmod")),
             own = make_linear_solver(named("cholmod"));
  EXPECT_FALSE(taken->order_like(*first)) << "nothing analysed yet: nothing to take";
  first->compute(A);
  ASSERT_TRUE(taken->order_like(*first));
  taken->compute(B);
  own->compute(B);
  EXPECT_EQ((taken->solve(b) - own->solve(b)).lpNorm<Eigen::Infinity>(), 0.0);
  EXPECT_EQ(taken->factor_nonzeros(), own->factor_nonzeros());
  EXPECT_GT(own->factor_nonzeros(), A.nonZeros() / 2);
  EXPECT_FALSE(make_linear_solver(named("pcg"))->order_like(*first)) << "an iterative solver has no ordering";

  // A star of n nodes around `hub` (diagonally dominant), and with `pairs` the other
  // nodes from 2 on joined in pairs: node 1, the only one of least degree, is then
  // ordered first.
  const int n = 60;
  const auto star = [n](int hub, bool pairs) {
    std::vector<Eigen::Triplet<double>> t;
    for (int i = 0; i < n; ++i) t.emplace_back(i, i, i == hub ? n + 1.0 : 4.0);
    for (int i = 0; i < n; ++i)
      if (i != hub) t.emplace_back(i, hub, -1.0), t.emplace_back(hub, i, -1.0);
    for (int i = 2; pairs && i + 1 < n; i += 2)
      if (i != hub && i + 1 != hub) t.emplace_back(i, i + 1, -1.0), t.emplace_back(i + 1, i, -1.0);
    SparseMatrix S(n, n);
    S.setFromTriplets(t.begin(), t.end());
    return S;
  };
  const SparseMatrix S0 = star(0, true), S1 = star(1, false);
  const Vector c = Vector::LinSpaced(n, 1.0, 3.0);
  const auto order = make_linear_solver(named("cholmod")), given = make_linear_solver(named("cholmod")),
             fresh = make_linear_solver(named("cholmod"));
  order->compute(S0);
  ASSERT_TRUE(given->order_like(*order));
  given->compute(S1);
  fresh->compute(S1);
  EXPECT_EQ(fresh->factor_nonzeros(), 2 * n - 1) << "its own ordering: the hub last, no fill";
  EXPECT_GT(given->factor_nonzeros(), n * (n - 1) / 4) << "the ordering given: the hub early, filled in";
  EXPECT_LT((S1 * given->solve(c) - c).norm(), 1e-12 * c.norm());
}

// A system factorised once per analysis (SystemDescription::factorized_once: the gradient
// step's Helmholtz systems) is ordered by AMD alone unless AMD's factor is costly enough
// for METIS to pay within a few factorisations (kMetisFlopsPerEntry, 6000 flops per entry
// of A): CHOLMOD's default tries METIS whenever AMD's factor is costly for a factor
// reused many times (at 5e5 nodes in 2D METIS took 3.1 s to save 0.25 s of each
// factorisation). 27-point 3D Laplacians on which CHOLMOD keeps METIS's ordering: of
// 20^3 unknowns (AMD: 5.7e3 flops per entry), told factorised once, the solver has AMD's
// larger fill; of 24^3 (AMD: 1.0e4), METIS's, as by default. Every one solves.
TEST(LinearSolver, CholmodOrdersASystemFactorisedOnceByMetisOnlyWhereAmdIsCostly) {
  const auto laplacian_27 = [](int m) {
    std::vector<Eigen::Triplet<double>> t;
    const auto id = [m](int i, int j, int k) { return (k * m + j) * m + i; };
    for (int k = 0; k < m; ++k)
      for (int j = 0; j < m; ++j)
        for (int i = 0; i < m; ++i) {
          t.emplace_back(id(i, j, k), id(i, j, k), 6.0);
          for (int c = -1; c <= 1; ++c)
            for (int b = -1; b <= 1; ++b)
              for (int a = -1; a <= 1; ++a) {
                const int x = i + a, y = j + b, z = k + c;
                if ((a || b || c) && x >= 0 && y >= 0 && z >= 0 && x < m && y < m && z < m)
                  t.emplace_back(id(i, j, k), id(x, y, z), -0.2);
              }
        }
    SparseMatrix A(m * m * m, m * m * m);
    A.setFromTriplets(t.begin(), t.end());
    return A;
  };
  SystemDescription system;
  system.factorized_once = true;
  for (const int m : {20, 24}) {
    const SparseMatrix A = laplacian_27(m);
    const Vector b = Vector::LinSpaced(A.rows(), -1.0, 2.0);
    const auto usual = make_linear_solver(named("cholmod")), once = make_linear_solver(named("cholmod"));
    once->describe(system);
    usual->compute(A);
    once->compute(A);
    if (m == 20)
      EXPECT_GT(once->factor_nonzeros(), 1.3 * usual->factor_nonzeros()) << "AMD's fill, not METIS's";
    else
      EXPECT_EQ(once->factor_nonzeros(), usual->factor_nonzeros()) << "METIS's fill, as by default";
    for (const auto* s : {usual.get(), once.get()}) EXPECT_LT((A * s->solve(b) - b).norm(), 1e-12 * b.norm()) << m;
  }
}

// A system of several unknowns per node told so (SystemDescription::block_size: the Newton
// tangent, dim per node) is ordered by AMD on the nodes' graph, expanded to the equations,
// with CHOLMOD's default rule after it (METIS too where AMD's factor is costly, the one
// with fewer entries kept): the factor has as many entries as CHOLMOD's default gives on
// the equations, a node's equations stay together, and it solves. Node systems A = L (x) B,
// B a 2 x 2 SPD block: a 2D 9-point Laplacian of 40^2 nodes (AMD's ordering kept) and a 3D
// 27-point one of 16^3 nodes, where CHOLMOD's default keeps METIS's (2.00e6 entries of L
// against AMD's 2.78e6: without the rule the node ordering would have AMD's).
TEST(LinearSolver, CholmodOrdersANodeBlockedSystemOnItsNodesGraphAsWellAsOnItsEquations) {
  const auto blocked = [](int m, int dim) {
    Eigen::Matrix2d B;
    B << 2.0, 0.5, 0.5, 1.0;
    std::vector<Eigen::Triplet<double>> t;
    const int nodes = dim == 2 ? m * m : m * m * m;
    const auto ijk = [m](int n) { return std::array<int, 3>{n % m, (n / m) % m, n / (m * m)}; };
    for (int a = 0; a < nodes; ++a)
      for (int b = 0; b < nodes; ++b) {
        const auto x = ijk(a), y = ijk(b);
        if (std::abs(x[0] - y[0]) > 1 || std::abs(x[1] - y[1]) > 1 || std::abs(x[2] - y[2]) > 1) continue;
        const double l = a == b ? (dim == 2 ? 8.5 : 26.5) : -1.0;
        for (int i = 0; i < 2; ++i)
          for (int j = 0; j < 2; ++j) t.emplace_back(2 * a + i, 2 * b + j, l * B(i, j));
      }
    SparseMatrix A(2 * nodes, 2 * nodes);
    A.setFromTriplets(t.begin(), t.end());
    return A;
  };
  SystemDescription by_nodes;
  by_nodes.block_size = 2;
  for (const int dim : {2, 3}) {
    const SparseMatrix A = blocked(dim == 2 ? 40 : 16, dim);
    const Vector b = Vector::LinSpaced(A.rows(), -1.0, 2.0);
    const auto usual = make_linear_solver(named("cholmod")), nodes = make_linear_solver(named("cholmod"));
    nodes->describe(by_nodes);
    usual->compute(A);
    nodes->compute(A);
    EXPECT_EQ(nodes->factor_nonzeros(), usual->factor_nonzeros()) << dim;
    if (dim == 3) EXPECT_LT(nodes->factor_nonzeros(), 2.1e6) << "METIS's ordering, as by default";
    const std::vector<int> perm = nodes->ordering();
    for (std::size_t k = 0; k + 1 < perm.size(); k += 2)  // a node's equations together
      ASSERT_EQ(perm[k] / 2, perm[k + 1] / 2) << k;
    for (const auto* s : {usual.get(), nodes.get()}) EXPECT_LT((A * s->solve(b) - b).norm(), 1e-12 * b.norm()) << dim;
  }
}

// An ordering made for another system on the same nodes (the load step's, given to the
// gradient step's scalar systems: LinearSolver::order_by with compare) is kept only where
// its factor costs fewer flops than CHOLMOD's own ordering's. The star of the test above
// with its hub early: AMD's ordering (hub last, no fill) is kept instead. A 27-point
// Laplacian of 20^3 unknowns factorised once, given the ordering CHOLMOD's default makes
// for it (METIS's): kept, with less fill than the AMD ordering the solver makes alone.
TEST(LinearSolver, CholmodKeepsAComparedOrderingOnlyWhereItsFactorIsCheaper) {
  const int n = 60;
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) t.emplace_back(i, i, i == 1 ? n + 1.0 : 4.0);
  for (int i = 0; i < n; ++i)
    if (i != 1) t.emplace_back(i, 1, -1.0), t.emplace_back(1, i, -1.0);
  SparseMatrix star(n, n);
  star.setFromTriplets(t.begin(), t.end());
  std::vector<int> hub_early(n);
  for (int i = 0; i < n; ++i) hub_early[i] = (i + 1) % n;  // 1, 2, ..., n - 1, 0
  const Vector c = Vector::LinSpaced(n, 1.0, 3.0);
  const auto taken = make_linear_solver(named("cholmod")), compared = make_linear_solver(named("cholmod"));
  ASSERT_TRUE(taken->order_by(hub_early));
  ASSERT_TRUE(compared->order_by(hub_early, true));
  taken->compute(star);
  compared->compute(star);
  EXPECT_GT(taken->factor_nonzeros(), n * (n - 1) / 4) << "taken as given: the hub first, filled in";
  EXPECT_EQ(compared->factor_nonzeros(), 2 * n - 1) << "compared: AMD's, the hub last, no fill";
  EXPECT_LT((star * compared->solve(c) - c).norm(), 1e-12 * c.norm());

  const int m = 20;
  t.clear();
  const auto id = [m](int i, int j, int k) { return (k * m + j) * m + i; };
  for (int k = 0; k < m; ++k)
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i)
        for (int e = -1; e <= 1; ++e)
          for (int b = -1; b <= 1; ++b)
            for (int a = -1; a <= 1; ++a) {
              const int x = i + a, y = j + b, z = k + e;
              if (x >= 0 && y >= 0 && z >= 0 && x < m && y < m && z < m)
                t.emplace_back(id(i, j, k), id(x, y, z), (a || b || e) ? -0.2 : 6.0);
            }
  SparseMatrix A(m * m * m, m * m * m);
  A.setFromTriplets(t.begin(), t.end());
  SystemDescription once;
  once.factorized_once = true;
  const auto usual = make_linear_solver(named("cholmod")), alone = make_linear_solver(named("cholmod")),
             given = make_linear_solver(named("cholmod"));
  usual->compute(A);
  alone->describe(once);
  alone->compute(A);
  given->describe(once);
  ASSERT_TRUE(given->order_by(usual->ordering(), true));
  given->compute(A);
  ASSERT_GT(alone->factor_nonzeros(), 1.3 * usual->factor_nonzeros()) << "alone: AMD's larger fill (test above)";
  EXPECT_EQ(given->factor_nonzeros(), usual->factor_nonzeros()) << "the ordering compared is the cheaper: kept";
  const Vector b = Vector::LinSpaced(A.rows(), -1.0, 2.0);
  EXPECT_LT((A * given->solve(b) - b).norm(), 1e-12 * b.norm());
}

TEST(LinearSolver, NonSymmetricMatrixIsSolvedByAGeneralSolverNeverSymmetrised) {
  // Strongly non-symmetric: the sub- and super-diagonals differ (either triangle,
  // symmetrised, is positive definite: a symmetric solver would not notice).
  const SparseMatrix A = tridiagonal(100, -0.2, -0.9);
  const Vector b = Vector::LinSpaced(100, 0.5, 2.0);
  for (const char* name : {"umfpack", "eigen-lu"}) {
    const auto s = make_linear_solver(named(name), MatrixKind::General);
    EXPECT_TRUE(s->general());
    s->compute(A);
    EXPECT_LT((A * s->solve(b) - b).norm(), 1e-12 * b.norm()) << name;
  }
  // A symmetric-only choice is not used for a general matrix: linear_solver.general is.
  for (const char* name : {"cholmod", "eigen-ldlt", "pcg"}) {
    const auto s = make_linear_solver(named(name), MatrixKind::General);
    EXPECT_EQ(s->name(), "umfpack") << name;
    s->compute(A);
    EXPECT_LT((A * s->solve(b) - b).norm(), 1e-12 * b.norm()) << name;
  }
  // What cholmod would do with it (read one triangle) is a different answer: the test
  // matrix really is one that symmetrising would get wrong.
  const auto chol = make_linear_solver(named("cholmod"));
  chol->compute(A);
  EXPECT_GT((A * chol->solve(b) - b).norm(), 1e-3 * b.norm());
}

TEST(LinearSolver, UnknownNamesAreRefusedWithTheRegisteredOnes) {
  try {
    make_linear_solver(named("mumps"));
    FAIL() << "expected SolverError";
  } catch (const SolverError& e) {
    EXPECT_NE(std::string(e.what()).find("\"cholmod\""), std::string::npos) << e.what();
  }
  LinearSolverSettings s;
  s.general = "cholmod";  // not a general solver
  EXPECT_THROW(make_linear_solver(s, MatrixKind::General), SolverError);
}

namespace {
/// A toy solver defined only here: Jacobi iterations to a tight tolerance, for
/// diagonally dominant matrices (recipe "add a linear solver", docs/architecture.md).
class ToyJacobi final : public LinearSolver {
 public:
  std::string name() const override { return "toy-jacobi"; }
  bool general() const override { return true; }

 protected:
  void do_analyze(const SparseMatrix&) override {}
  void do_factorize(const SparseMatrix& A) override { A_ = A; }
  Vector do_solve(const Vector& b) const override {
    Vector x = Vector::Zero(b.size());
    const Vector d = A_.diagonal();
    for (int it = 0; it < 10000 && (A_ * x - b).norm() > 1e-14 * b.norm(); ++it) x += (b - A_ * x).cwiseQuotient(d);
    return x;
  }

 private:
  SparseMatrix A_;
};
}  // namespace

TEST(LinearSolver, ASolverDefinedInATestJoinsTheRegistryWithOneCall) {
  LinearSolverRegistry::instance().add(
      {"toy-jacobi", "Jacobi iterations (test only)", true,
       [](const LinearSolverSettings&, MatrixKind) { return std::make_unique<ToyJacobi>(); }});
  const SparseMatrix A = tridiagonal(50, -0.5, -0.3);
  const Vector b = Vector::LinSpaced(50, 1.0, 2.0);
  const auto s = make_linear_solver(named("toy-jacobi"), MatrixKind::General);
  EXPECT_EQ(s->name(), "toy-jacobi");
  s->compute(A);
  const auto lu = make_linear_solver(named("umfpack"));
  lu->compute(A);
  EXPECT_LT((s->solve(b) - lu->solve(b)).norm(), 1e-12 * b.norm());
  EXPECT_NE(LinearSolverRegistry::instance().quoted_names().find("\"toy-jacobi\""), std::string::npos);
}

TEST(LinearSolver, PreconditionedCgSolvesAndReportsFailure) {  // 2D five-point Laplacian (+ a small shift): incomplete
                                                               // Cholesky is not exact here.
  const SparseMatrix A = test::laplacian_2d(30);
  const int n = static_cast<int>(A.rows());
  const Vector b = Vector::LinSpaced(n, -1.0, 1.0);
  const auto chol = make_linear_solver(named("cholmod")), pcg = make_linear_solver(named("pcg"));
  chol->compute(A);
  pcg->compute(A);
  const Vector x = chol->solve(b);
  EXPECT_LT((pcg->solve(b) - x).norm(), 1e-8 * x.norm());
  LinearSolverSettings s = named("pcg");
  s.pcg_max_iterations = 2;
  s.pcg_tolerance = 1e-14;
  const auto limited = make_linear_solver(s);
  limited->compute(A);
  try {
    limited->solve(b);
    FAIL() << "expected SolverError";
  } catch (const SolverError& e) {
    EXPECT_NE(std::string(e.what()).find("preconditioned CG did not converge"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("after 2 iterations"), std::string::npos) << e.what();
  }
}

TEST(LinearSolver, IndefiniteMatrixIsReportedBySpdSolvers) {
  SparseMatrix A(2, 2);
  A.insert(0, 0) = 1.0;
  A.insert(1, 1) = -1.0;
  for (const char* name : {"cholmod", "eigen-ldlt"}) {  // PCG: see above
    const auto s = make_linear_solver(named(name));
    EXPECT_THROW(s->compute(A), SolverError) << name;
  }
}

// CHOLMOD runs its own OpenMP regions serially under OpenBLAS (or with dynamic adjustment
// under the reference BLAS) only for the duration of each call: the caller's settings,
// and so the threads of gradmpm's own point loops, are as they were afterwards.
TEST(LinearSolver, CholmodLeavesTheCallersOpenMpSettingsAsTheyWere) {
  const int threads = omp_get_max_threads(), dynamic = omp_get_dynamic(), levels = omp_get_max_active_levels();
  omp_set_num_threads(2);
  omp_set_dynamic(0);
  omp_set_max_active_levels(3);
  const SparseMatrix A = test::laplacian_2d(40);
  const Vector b = Vector::Ones(A.rows());
  const auto s = make_linear_solver(named("cholmod"));
  s->compute(A);
  const Vector x = s->solve(b);
  EXPECT_LT((A * x - b).norm(), 1e-12 * b.norm());
  EXPECT_EQ(omp_get_dynamic(), 0);
  EXPECT_EQ(omp_get_max_active_levels(), 3);
  int team = 0;
#pragma omp parallel
  {
#pragma omp single
    team = omp_get_num_threads();
  }
  EXPECT_EQ(team, 2) << "a parallel region after CHOLMOD gets the threads asked for";
  omp_set_num_threads(threads);
  omp_set_dynamic(dynamic);
  omp_set_max_active_levels(levels);
}

// Requirement: a released factor (LinearSolver::release_factor, called by the Newton driver
// once a load step has converged) is never solved with, and the next factorisation of the
// kept analysis gives the answer of one that was never released, bit for bit.
TEST(LinearSolver, CholmodReleasesItsFactorAndFactorisesAgainOnItsAnalysis) {
  const SparseMatrix A = test::laplacian_2d(60);
  const Vector b = Vector::LinSpaced(A.rows(), -1.0, 2.0);
  const auto kept = make_linear_solver(named("cholmod")), released = make_linear_solver(named("cholmod"));
  kept->compute(A);
  released->compute(A);
  const double analysis = released->analysis_seconds();
  released->release_factor();
  EXPECT_THROW((void)released->solve(b), SolverError);
  released->release_factor();  // twice: nothing more to free
  SparseMatrix B = A;
  B.coeffs() *= 2.0;  // new values on the same pattern
  kept->factorize(B);
  released->factorize(B);
  EXPECT_EQ(released->analysis_seconds(), analysis) << "the analysis was kept";
  const Vector x = released->solve(b);
  EXPECT_TRUE(x == kept->solve(b));
  EXPECT_LT((B * x - b).norm(), 1e-12 * b.norm());
}
