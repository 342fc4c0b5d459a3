#pragma once
// One table of the named point fields every MPM output draws from: the VTU files,
// points_final.csv, points_gradient.csv and tracked_points.csv each pick columns by
// name, so a field is defined once. The materials' state variables are columns too
// (Material::state_variables): every one reaches the VTU files and points_final.csv by
// name; a state variable named like a fixed column (elastic_strain) is that column.
// Vector columns write x, y, z (zero beyond dim); tensor columns 9 VTU components
// (row-major) and 6 CSV ones in the order xx, yy, zz, xy, yz, xz.
#include <functional>
#include <string>
#include <vector>

#include "gradmpm/gradient/MpmGradient.hpp"
#include "gradmpm/io/Csv.hpp"
#include "gradmpm/io/Vtk.hpp"

namespace gradmpm {

struct PointColumn {
  enum class Kind { Scalar, Vector, SymmetricTensor };
  std::string name;  ///< VTU array name
  Kind kind = Kind::Scalar;
  std::vector<std::string> csv;  ///< CSV column names (1, 3 or 6)
  bool integer = false;          ///< VTU Int64
  /// Writes point p's value: 1, 3 or 9 (row-major 3x3) numbers.
  std::function<void(int p, double* out)> value;
  int vtk_components() const { return kind == Kind::Scalar ? 1 : (kind == Kind::Vector ? 3 : 9); }
};

template <int dim>
class PointColumns {
 public:
  /// `gradient`: the enriched fields, or null when there are none (their columns are absent).
  PointColumns(const Model<dim>& model, const EnrichedFields<dim>* gradient);

  bool has(const std::string& name) const;
  const PointColumn& column(const std::string& name) const;
  /// The state-variable columns, in the order the materials declare them.
  const std::vector<std::string>& state_columns() const { return state_; }
  /// `names` followed by the state columns not among them.
  std::vector<std::string> with_state(std::vector<std::string> names) const;

  /// A VTU file of the points [first, last) (last < 0: to the end) at their current
  /// positions with the named columns.
  std::string vtu(const std::vector<std::string>& names, int first = 0, int last = -1) const;
  /// The named columns' VTK layout (names, components, types; no values), for a .pvtu.
  std::vector<VtkField> vtk_layout(const std::vector<std::string>& names) const;
  /// The named columns as a CSV table (one row per point).
  CsvTable csv(const std::vector<std::string>& names) const;
  /// CSV header names of the named columns.
  std::vector<std::string> csv_header(const std::vector<std::string>& names) const;
  /// Appends one CSV row per listed point: `lead` values, then the named columns.
  void append_rows(std::string& out, const std::vector<double>& lead, const std::vector<long long>& points,
                   const std::vector<std::string>& names) const;

 private:
  void add(PointColumn c) { columns_.push_back(std::move(c)); }
  const Model<dim>& model_;
  std::vector<PointColumn> columns_;
  std::vector<std::string> state_;
};

/// The columns of the points' VTU files.
template <int dim>
std::vector<std::string> vtu_point_columns(const PointColumns<dim>& table);

/// grid_NNNN.vtu: the step's displacement increment and nodal mass (zero without a step)
/// at every grid node (a distributed run's: at the corners of the rank's cells only, its
/// piece's points, in vtu_grid's order; a collective call then, as StepInfo's grid fields are).
template <int dim>
std::vector<VtkField> grid_vtk_fields(const Model<dim>& m, const StepInfo* info);

/// The grid's VTU of `fields` (grid_vtk_fields): every cell, or a distributed run's
/// piece, the cells of the rank's box (Model::rank_boxes).
template <int dim>
std::string grid_vtu(const Model<dim>& m, const std::vector<VtkField>& fields);

}  // namespace gradmpm
