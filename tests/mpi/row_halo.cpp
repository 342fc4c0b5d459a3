// Requirement (docs/parallel.md): on any number of
// ranks, RowHalo's neighbour exchanges give each rank what a sum of the whole vector over
// the ranks gave, in every row it owns or reads (its ghost rows), the same bits on every
// rank that holds a row, for one vector or several columns at once; its norms (several
// with one reduction) are the whole summed vectors' norms; likewise with a local numbering
// (each rank's vector holding its own rows first, then the others it touches by increasing
// global row, as DofMap numbers a distributed load step).
// Run: mpirun -n N row_halo_check (exit 0: every check held).
// Each rank touches a random set of rows spread over the whole vector (far more ghosts
// than a load step has, and ranks that touch none of some owner's rows), with values
// that make every sum exact in floating point (small integers).
#include <cmath>
#include <cstdio>
#include <vector>

#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/solver/RowHalo.hpp"

using namespace gradmpm;

int main(int argc, char** argv) {
  ranks::Session session(&argc, &argv);
  const int size = ranks::size(), me = ranks::rank(), n = 997;
  int failures = 0;
  auto fail = [&](const char* what, int row, double got, double expected) {
    if (failures++ < 10) std::fprintf(stderr, "rank %d: %s, row %d: %.17g, expected %.17g\n", me, what, row, got, expected);
  };
  // Uneven rows by rank, one rank with none when there are several.
  std::vector<int> rank_rows(size + 1, 0);
  for (int r = 1; r < size; ++r) rank_rows[r] = r == 1 && size > 2 ? 0 : static_cast<int>(1LL * n * r * r / (size * size));
  rank_rows[size] = n;
  // Rank r's partial vector: value (r + 1) * (row % 7 + 1) in its touched rows, zero elsewhere.
  auto touches = [](int r, int row) { return ((row * 31 + r * 17) % 5 == 0) || (row % 97 == r); };
  std::vector<int> touched;
  Vector v = Vector::Zero(n), summed = Vector::Zero(n);
  for (int row = 0; row < n; ++row) {
    for (int r = 0; r < size; ++r)
      if (touches(r, row) || (row >= rank_rows[r] && row < rank_rows[r + 1])) summed[row] += (r + 1) * (row % 7 + 1);
    if (touches(me, row) || (row >= rank_rows[me] && row < rank_rows[me + 1])) {
      touched.push_back(row);
      v[row] = (me + 1) * (row % 7 + 1);
    }
  }
  const RowHalo halo(rank_rows, touched);
  Vector w = v;
  halo.sum(w);
  for (const int row : touched)
    if (w[row] != summed[row]) fail("sum", row, w[row], summed[row]);
  Vector owners = v;
  halo.add_to_owners(owners);
  for (int row = rank_rows[me]; row < rank_rows[me + 1]; ++row)
    if (owners[row] != summed[row]) fail("add_to_owners", row, owners[row], summed[row]);
  const double expected = summed.norm();
  const Vector twice = 2.0 * w;
  const auto both = halo.norms<2>({&w, &twice});  // one reduction for several vectors
  if (std::abs(both[0] - expected) > 1e-14 * expected) fail("norms[0]", -1, both[0], expected);
  if (std::abs(both[1] - 2.0 * expected) > 1e-14 * expected) fail("norms[1]", -1, both[1], 2.0 * expected);
  // Several columns at once (the gradient step's fields): column j is (j + 1) times the
  // vector, and sum gives each column's sum, the same bits as column by column.
  Eigen::MatrixXd columns(n, 3);
  for (int j = 0; j < 3; ++j) columns.col(j) = (j + 1.0) * v;
  halo.sum(columns);
  for (const int row : touched)
    for (int j = 0; j < 3; ++j)
      if (columns(row, j) != (j + 1.0) * summed[row]) fail("sum of columns", row, columns(row, j), (j + 1.0) * summed[row]);
  Eigen::MatrixXd fetched = Eigen::MatrixXd::Zero(n, 2);
  for (int row = rank_rows[me]; row < rank_rows[me + 1]; ++row) fetched.row(row) << row, -row;
  halo.fetch_ghosts(fetched);
  for (const int row : touched)
    if (fetched(row, 0) != row || fetched(row, 1) != -row) fail("fetch_ghosts of columns", row, fetched(row, 0), row);
  // Local numbering: own rows (global rank_rows[me]...) first, then the touched others.
  std::vector<int> globals;
  for (int row = rank_rows[me]; row < rank_rows[me + 1]; ++row) globals.push_back(row);
  for (const int row : touched)
    if (row < rank_rows[me] || row >= rank_rows[me + 1]) globals.push_back(row);
  const int held = static_cast<int>(globals.size());
  std::vector<int> local_touched(held);
  for (int k = 0; k < held; ++k) local_touched[k] = k;
  const RowHalo local(rank_rows, local_touched, globals);
  if (local.first() != 0 || local.last() != rank_rows[me + 1] - rank_rows[me])
    fail("local own rows", -1, local.last(), rank_rows[me + 1] - rank_rows[me]);
  Vector lv(held);
  for (int k = 0; k < held; ++k) lv[k] = v[globals[k]];
  Vector lw = lv;
  local.sum(lw);
  for (int k = 0; k < held; ++k)
    if (lw[k] != summed[globals[k]]) fail("local sum", globals[k], lw[k], summed[globals[k]]);
  const auto local_norm = local.norms<1>({&lw});
  if (std::abs(local_norm[0] - expected) > 1e-14 * expected) fail("local norm", -1, local_norm[0], expected);
  Eigen::MatrixXd local_fetched = Eigen::MatrixXd::Zero(held, 2);
  for (int k = 0; k < local.last(); ++k) local_fetched.row(k) << globals[k], -globals[k];
  local.fetch_ghosts(local_fetched);
  for (int k = 0; k < held; ++k)
    if (local_fetched(k, 0) != globals[k] || local_fetched(k, 1) != -globals[k])
      fail("local fetch_ghosts", globals[k], local_fetched(k, 0), globals[k]);
  long long ghosts = static_cast<long long>(halo.ghost_rows());
  if (static_cast<long long>(local.ghost_rows()) != ghosts)
    fail("local ghost rows", -1, static_cast<int>(local.ghost_rows()), static_cast<int>(ghosts));
  if (size > 1 && ghosts == 0) fail("no ghost rows", -1, 0, 1);
  int failed = failures;
  ranks::max(&failed, 1);
  if (me == 0)
    std::printf("%d ranks, %lld ghost rows on rank 0: %s\n", size, ghosts, failed ? "FAILED" : "sums, fetches and norms as over the whole vector");
  return failed ? 1 : 0;
}
