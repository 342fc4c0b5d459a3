#include "gradmpm/app/ColumnCheck.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "gradmpm/analytic/Column.hpp"
#include "gradmpm/io/Csv.hpp"
#include "gradmpm/io/EmbeddedScripts.hpp"
#include "gradmpm/io/Python.hpp"
#include "gradmpm/io/StagedOutputs.hpp"

namespace gradmpm {

/// Compares the final state with the column closed form; writes column_check.csv and
/// (if asked) column.png; returns a one-line summary.
template <int dim>
std::string column_check(const Model<dim>& m, const std::filesystem::path& dir, bool plot) {
  const auto& P = m.points;
  double base = std::numeric_limits<double>::max(), top = std::numeric_limits<double>::lowest();
  for (int p = 0; p < P.size(); ++p) {
    base = std::min(base, P.original_position[p][dim - 1] - P.original_half_length[p][dim - 1]);
    top = std::max(top, P.original_position[p][dim - 1] + P.original_half_length[p][dim - 1]);
  }
  const auto* mat = m.materials[0].get();
  // Young's modulus from the tangent at rest (nu = 0: A_yyyy = E).
  std::vector<double> state_n(mat->state_size()), state(mat->state_size());
  mat->initial_state(state_n.data());
  MaterialResponse r;
  mat->update(Eigen::Matrix3d::Identity(), state_n.data(), state.data(), r);
  Mat9 A;
  mat->tangent(r, dim, A);
  const analytic::Column col{top - base, mat->density(), -m.gravity[dim - 1],
                             A(3 * (dim - 1) + dim - 1, 3 * (dim - 1) + dim - 1)};
  std::vector<double> Y, s, se, y, ye;
  double err_s = 0, err_y = 0;
  for (int p = 0; p < P.size(); ++p) {
    Y.push_back(P.original_position[p][dim - 1] - base);
    s.push_back(P.stress[p](dim - 1, dim - 1));
    se.push_back(col.cauchy_stress(Y.back()));
    y.push_back(P.position[p][dim - 1] - base);
    ye.push_back(col.position(Y.back()));
    err_s = std::max(err_s, std::abs(s.back() - se.back()));
    err_y = std::max(err_y, std::abs(y.back() - ye.back()));
  }
  CsvTable t;
  t.add("Y", Y);
  t.add("stress", s);
  t.add("stress_exact", se);
  t.add("y", y);
  t.add("y_exact", ye);
  StagedOutputs out(dir);
  const auto csv = out.write_text("column_check.csv", t.str());
  if (plot) {
    const auto png = out.stage("column.png");
    run_python_script(embedded::plot_column_py,
                      {csv.string(), png.string(),
                       fmt::format("{}D column, {} basis, {} points", dim, to_string(m.basis), P.size())});
  }
  out.commit();
  return fmt::format(
      "column vs closed form: max |stress error| / (rho0 g H0) = {:.3e}, max |position error| / H0 = {:.3e}",
      err_s / (col.density * col.gravity * col.height), err_y / col.height);
}

template std::string column_check<1>(const Model<1>&, const std::filesystem::path&, bool);
template std::string column_check<2>(const Model<2>&, const std::filesystem::path&, bool);
template std::string column_check<3>(const Model<3>&, const std::filesystem::path&, bool);

}  // namespace gradmpm
