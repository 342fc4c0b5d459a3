// Requirements on the grid, the standard MPM basis and the Gauss-point generator,
// checked in 1D, 2D and 3D (they are templates on the dimension).
#include <gtest/gtest.h>

#include <cmath>

#include "gradmpm/basis/LinearBasis.hpp"
#include "gradmpm/points/Generate.hpp"
#include "gradmpm/points/Transfer.hpp"

using namespace gradmpm;

template <int dim>
Grid<dim> make_grid() {
  Vec<dim> origin, h;
  typename Grid<dim>::Index cells;
  for (int d = 0; d < dim; ++d) {
    origin[d] = -1.0 + 0.25 * d;
    h[d] = 0.5 + 0.1 * d;
    cells[d] = 3 + d;
  }
  return Grid<dim>(origin, h, cells);
}

template <int dim>
void check_basis() {
  const Grid<dim> grid = make_grid<dim>();
  Vec<dim> a;  // coefficients of a linear field q(x) = 0.7 + a.x
  for (int d = 0; d < dim; ++d) a[d] = 1.0 + d;
  for (int trial = 0; trial < 50; ++trial) {
    Vec<dim> x;
    for (int d = 0; d < dim; ++d)
      x[d] = grid.origin()[d] + grid.cell_size()[d] * grid.cells()[d] * std::fmod(0.137 * (trial + 1) * (d + 1), 1.0);
    Stencil<dim> s;
    ASSERT_TRUE(LinearBasis<dim>::evaluate(grid, x, s));
    ASSERT_EQ(s.count, 1 << dim);
    double sumN = 0, q = 0;
    Vec<dim> sumdN = Vec<dim>::Zero(), gradq = Vec<dim>::Zero();
    for (int i = 0; i < s.count; ++i) {
      const Vec<dim> xn = grid.node_position(s.node[i]);
      const double qn = 0.7 + a.dot(xn);
      sumN += s.N[i];
      sumdN += s.dN[i];
      q += s.N[i] * qn;
      gradq += s.dN[i] * qn;
    }
    EXPECT_NEAR(sumN, 1.0, 1e-14) << "partition of unity";
    EXPECT_LT(sumdN.norm(), 1e-12) << "gradients of a partition of unity sum to zero";
    EXPECT_NEAR(q, 0.7 + a.dot(x), 1e-13) << "linear fields are reproduced";
    EXPECT_LT((gradq - a).norm(), 1e-12) << "their gradients too";
  }
  Vec<dim> outside = grid.origin();
  outside[0] -= 1e-9;
  Stencil<dim> s;
  EXPECT_FALSE(LinearBasis<dim>::evaluate(grid, outside, s));
}

TEST(LinearBasis, PartitionOfUnityAndLinearCompleteness1D) { check_basis<1>(); }
TEST(LinearBasis, PartitionOfUnityAndLinearCompleteness2D) { check_basis<2>(); }
TEST(LinearBasis, PartitionOfUnityAndLinearCompleteness3D) { check_basis<3>(); }

TEST(Grid, NodeNumberingRoundTrips) {
  const Grid<3> grid = make_grid<3>();
  for (int n = 0; n < grid.num_nodes(); ++n) EXPECT_EQ(grid.node_index(grid.node_ijk(n)), n);
  EXPECT_EQ(grid.num_nodes(), 4 * 5 * 6);
  EXPECT_EQ(grid.num_cells(), 3 * 4 * 5);
}

// Requirement: n Gauss points per direction integrate polynomials of degree 2n-1 exactly,
// so the points of a cell are exact FEM quadrature for the operators built on them.
TEST(GaussPoints, IntegratePolynomialsExactly) {
  const Grid<2> grid(Vec<2>(0.0, 0.0), Vec<2>(0.5, 0.25), {4, 8});
  for (int n = 1; n <= 4; ++n) {
    MaterialPoints<2> pts;
    add_gauss_points<2>(
        grid, {0, 0}, {4, 8}, n, [](const Vec<2>&) { return 0; }, pts);
    ASSERT_EQ(pts.size(), 32 * n * n);
    const int deg = 2 * n - 1;
    double integral = 0, volume = 0;
    for (int p = 0; p < pts.size(); ++p) {
      integral += std::pow(pts.position[p][0], deg) * std::pow(pts.position[p][1], deg) * pts.volume[p];
      volume += pts.volume[p];
    }
    const double exact = std::pow(2.0, deg + 1) / (deg + 1) * std::pow(2.0, deg + 1) / (deg + 1);
    EXPECT_NEAR(volume, 4.0, 1e-13);
    EXPECT_NEAR(integral, exact, 1e-11 * exact) << n << " points";
  }
}

// Requirement: points outside the grid are reported with their ids, not silently dropped.
TEST(Transfer, PointsOutsideTheGridAreListed) {
  const Grid<1> grid(Vec<1>(0.0), Vec<1>(1.0), {4});
  MaterialPoints<1> pts;
  pts.add(Vec<1>(0.5), 1.0, 0);
  pts.add(Vec<1>(4.5), 1.0, 0);
  pts.add(Vec<1>(-0.1), 1.0, 0);
  try {
    evaluate_stencils<1, LinearBasis<1>>(grid, pts);
    FAIL() << "expected std::out_of_range";
  } catch (const std::out_of_range& e) {
    EXPECT_NE(std::string(e.what()).find("2 material point(s) outside the grid (ids): 1, 2"), std::string::npos)
        << e.what();
  }
}

// Requirement: a GIMP domain stretched wider than a cell (cpGIMP) is named as such, not
// reported as a point outside the grid.
TEST(Transfer, GimpDomainsWiderThanACellAreNamed) {
  const Grid<1> grid(Vec<1>(0.0), Vec<1>(1.0), {6});
  MaterialPoints<1> pts;
  pts.add(Vec<1>(2.5), 1.0, 0);
  pts.add(Vec<1>(3.5), 1.0, 0);
  pts.add(Vec<1>(-0.5), 1.0, 0);
  pts.half_length[0] = Vec<1>(0.25);
  pts.half_length[1] = Vec<1>(0.6);  // wider than h / 2
  pts.half_length[2] = Vec<1>(0.25);
  try {
    evaluate_stencils<1, GimpBasis<1>>(grid, pts);
    FAIL() << "expected std::out_of_range";
  } catch (const std::out_of_range& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("1 material point(s) outside the grid (ids): 2"), std::string::npos) << what;
    EXPECT_NE(what.find("1 material point(s) whose GIMP domain is wider than a grid cell (ids): 1"), std::string::npos)
        << what;
  }
}
