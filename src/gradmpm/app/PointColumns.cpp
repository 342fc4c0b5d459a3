#include "gradmpm/app/PointColumns.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/core/SymmetricTensor.hpp"
#include "gradmpm/io/Vtk.hpp"
#include "gradmpm/mpm/InitialStress.hpp"

namespace gradmpm {

namespace {
using Kind = PointColumn::Kind;

std::vector<std::string> suffixed(const std::string& prefix, const std::string& suffix, bool tensor) {
  std::vector<std::string> names;
  if (tensor)
    for (const auto& c : kSymmetricComponents) names.push_back(prefix + c.name + suffix);
  else
    for (const char* a : {"x", "y", "z"}) names.push_back(prefix + a + suffix);
  return names;
}

template <int dim>
void put(const Vec<dim>& v, double* out) {
  for (int d = 0; d < 3; ++d) out[d] = d < dim ? v[d] : 0.0;
}
void put(const Mat3& t, double* out) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out[3 * i + j] = t(i, j);
}
}  // namespace

template <int dim>
PointColumns<dim>::PointColumns(const Model<dim>& m, const EnrichedFields<dim>* g) : model_(m) {
  const auto& P = m.points;
  add({"id", Kind::Scalar, {"id"}, true, [&m](int p, double* o) { *o = m.id_of(p); }});
  add({"original_position", Kind::Vector, {"X", "Y", "Z"}, false, [&P](int p, double* o) {
         put<dim>(P.original_position[p], o);
       }});
  add({"position", Kind::Vector, suffixed("", "", false), false,
       [&P](int p, double* o) { put<dim>(P.position[p], o); }});
  add({"displacement", Kind::Vector, suffixed("u", "", false), false,
       [&P](int p, double* o) { put<dim>(Vec<dim>(P.position[p] - P.original_position[p]), o); }});
  add({"stress", Kind::SymmetricTensor, suffixed("s", "", true), false,
       [&P](int p, double* o) { put(P.stress[p], o); }});
  add({"elastic_strain", Kind::SymmetricTensor, suffixed("e", "", true), false,
       [&m](int p, double* o) { put(m.elastic_strain(p), o); }});
  add({"volume", Kind::Scalar, {"volume"}, false, [&P](int p, double* o) { *o = P.volume[p]; }});
  add({"mass", Kind::Scalar, {"mass"}, false, [&P](int p, double* o) { *o = P.mass[p]; }});
  add({"work", Kind::Scalar, {"work"}, false, [&P](int p, double* o) { *o = P.work[p]; }});
  add({"dissipation", Kind::Scalar, {"dissipation"}, false, [&m](int p, double* o) {
         *o = m.points.work[p] - m.elastic_energy(p);
       }});
  add({"material", Kind::Scalar, {"material"}, true, [&P](int p, double* o) { *o = P.material[p]; }});
  add({"velocity", Kind::Vector, suffixed("v", "", false), false,
       [&P](int p, double* o) { put<dim>(P.velocity[p], o); }});  // (a dynamic run's outputs)
  add({"pore_pressure", Kind::Scalar, {"p"}, false,
       [&P](int p, double* o) { *o = P.pore_pressure[p]; }});  // (a run with pore pressure)
  add({"excess_pore_pressure", Kind::Scalar, {"p_excess"}, false, [&m](int p, double* o) {
         *o = m.points.pore_pressure[p] - hydrostatic_pressure(m, p);
       }});  // (a run with a water table)
  if (g) {
    add({"gradient_displacement", Kind::Vector, suffixed("u", "_g", false), false,
         [g](int p, double* o) { put<dim>(g->displacement[p], o); }});
    add({"gradient_strain", Kind::SymmetricTensor, suffixed("e", "_g", true), false,
         [g](int p, double* o) { put(g->strain[p], o); }});
    add({"gradient_stress", Kind::SymmetricTensor, suffixed("s", "_g", true), false,
         [g](int p, double* o) { put(g->stress[p], o); }});
  }
  // State variables of every material, by name (first declaration wins the order). A
  // point whose material lacks a variable writes zero.
  for (std::size_t mi = 0; mi < m.materials.size(); ++mi) {
    for (const StateVariable& v : m.materials[mi]->state_variables()) {
      if (std::find(state_.begin(), state_.end(), v.name) != state_.end()) continue;
      state_.push_back(v.name);
      if (has(v.name)) continue;                         // a fixed column (elastic_strain) already reports it
      std::vector<int> offsets(m.materials.size(), -1);  // where each material keeps it
      for (std::size_t mj = 0; mj < m.materials.size(); ++mj) {
        int off = 0;
        for (const StateVariable& w : m.materials[mj]->state_variables()) {
          if (w.name == v.name && w.kind == v.kind) offsets[mj] = off;
          off += w.size();
        }
      }
      const bool tensor = v.kind == StateVariable::Kind::SymmetricTensor;
      add({v.name, tensor ? Kind::SymmetricTensor : Kind::Scalar,
           tensor ? suffixed(v.name + "_", "", true) : std::vector<std::string>{v.name}, false,
           [&m, offsets, tensor](int p, double* o) {
             const int off = offsets[m.points.material[p]];
             if (!m.state_initialised() || off < 0) {
               std::fill(o, o + (tensor ? 9 : 1), 0.0);
               return;
             }
             const double* s = m.points.state_of(p) + off;
             if (tensor)
               put(unpack_symmetric(s), o);
             else
               *o = *s;
           }});
    }
  }
}

template <int dim>
bool PointColumns<dim>::has(const std::string& name) const {
  for (const auto& c : columns_)
    if (c.name == name) return true;
  return false;
}

template <int dim>
const PointColumn& PointColumns<dim>::column(const std::string& name) const {
  for (const auto& c : columns_)
    if (c.name == name) return c;
  throw std::logic_error("no point column " + name);
}

template <int dim>
std::vector<std::string> PointColumns<dim>::with_state(std::vector<std::string> names) const {
  for (const auto& s : state_)
    if (std::find(names.begin(), names.end(), s) == names.end()) names.push_back(s);
  return names;
}

template <int dim>
std::string PointColumns<dim>::vtu(const std::vector<std::string>& names, int first, int last) const {
  if (last < 0) last = model_.points.size();
  const int np = last - first;
  std::vector<double> xyz(3 * static_cast<std::size_t>(np));
  for (int p = 0; p < np; ++p) put<dim>(model_.points.position[first + p], &xyz[3 * p]);
  std::vector<VtkField> fields = vtk_layout(names);
  for (auto& f : fields) {
    const PointColumn& c = column(f.name);
    f.values.resize(static_cast<std::size_t>(np) * f.components);
    for (int p = 0; p < np; ++p) c.value(first + p, &f.values[static_cast<std::size_t>(p) * f.components]);
  }
  return vtu_points(xyz, fields);
}

template <int dim>
std::vector<VtkField> PointColumns<dim>::vtk_layout(const std::vector<std::string>& names) const {
  std::vector<VtkField> layout;
  for (const auto& name : names) {
    const PointColumn& c = column(name);
    layout.push_back({c.name, c.vtk_components(), {}, c.integer});
  }
  return layout;
}

namespace {
/// The CSV components of a column's value: all of a scalar or vector, the six
/// independent ones of a tensor.
void csv_values(const PointColumn& c, const double* v, double* out) {
  if (c.kind != Kind::SymmetricTensor) {
    std::copy(v, v + c.vtk_components(), out);
    return;
  }
  for (int k = 0; k < 6; ++k) out[k] = v[3 * kSymmetricComponents[k].i + kSymmetricComponents[k].j];
}
}  // namespace

template <int dim>
CsvTable PointColumns<dim>::csv(const std::vector<std::string>& names) const {
  const int np = model_.points.size();
  CsvTable t;
  double v[9], out[9];
  for (const auto& name : names) {
    const PointColumn& c = column(name);
    std::vector<std::vector<double>> cols(c.csv.size(), std::vector<double>(np));
    for (int p = 0; p < np; ++p) {
      c.value(p, v);
      csv_values(c, v, out);
      for (std::size_t k = 0; k < c.csv.size(); ++k) cols[k][p] = out[k];
    }
    for (std::size_t k = 0; k < c.csv.size(); ++k) t.add(c.csv[k], std::move(cols[k]));
  }
  return t;
}

template <int dim>
std::vector<std::string> PointColumns<dim>::csv_header(const std::vector<std::string>& names) const {
  std::vector<std::string> h;
  for (const auto& name : names)
    for (const auto& n : column(name).csv) h.push_back(n);
  return h;
}

template <int dim>
void PointColumns<dim>::append_rows(std::string& out, const std::vector<double>& lead,
                                    const std::vector<long long>& points, const std::vector<std::string>& names) const {
  double v[9], vals[9];
  for (long long p : points) {
    std::string row;
    for (double x : lead) fmt::format_to(std::back_inserter(row), "{}{}", row.empty() ? "" : ",", x);
    for (const auto& name : names) {
      const PointColumn& c = column(name);
      c.value(static_cast<int>(p), v);
      csv_values(c, v, vals);
      for (std::size_t k = 0; k < c.csv.size(); ++k)
        fmt::format_to(std::back_inserter(row), "{}{}", row.empty() ? "" : ",", vals[k]);
    }
    out += row + '\n';
  }
}

template <int dim>
std::vector<std::string> vtu_point_columns(const PointColumns<dim>& table) {
  std::vector<std::string> names = {"displacement", "stress",      "elastic_strain", "volume", "mass",
                                    "work",         "dissipation", "material",       "id"};
  if (table.has("gradient_displacement"))
    for (const char* n : {"gradient_displacement", "gradient_strain", "gradient_stress"}) names.push_back(n);
  return table.with_state(names);
}

namespace {
/// A distributed run's grid piece: the cells of this rank's box.
template <int dim>
std::vector<int> piece_cells(const Model<dim>& m) {
  std::vector<int> keys;
  m.rank_boxes.for_each_cell(ranks::rank(), [&](int key) { keys.push_back(key); });
  return keys;
}
}  // namespace

template <int dim>
std::vector<VtkField> grid_vtk_fields(const Model<dim>& m, const StepInfo* info) {
  // Serially at every grid node; a distributed run's at its piece's points only (the
  // corners of its cells), so that no rank holds an output array as long as the grid.
  const bool split = !m.rank_boxes.empty();
  std::vector<int> at;  // the piece's points (split)
  if (split) at = cell_corners(m.grid, piece_cells(m));
  const std::size_t nn = split ? at.size() : static_cast<std::size_t>(m.grid.num_nodes());
  VtkField du{"displacement_increment", 3, std::vector<double>(3 * nn, 0.0)}, mass{"mass", 1, std::vector<double>(nn, 0.0)};
  if (info) {
    const Vector &u = info->grid_displacement(), &nodal_mass = info->grid_mass();
    const std::vector<int> listed = split ? info->grid_nodes() : std::vector<int>{};
    for (std::size_t k = 0; k < nn; ++k) {
      Eigen::Index n = static_cast<Eigen::Index>(k);  // where the k-th point's values are
      if (split) {
        n = listed_position(listed, at[k]);
        if (n < 0) continue;  // an inactive corner: zero
      }
      for (int d = 0; d < dim; ++d) du.values[3 * k + d] = u[n * dim + d];
      mass.values[k] = nodal_mass[n];
    }
  }
  if (info && info->grid_pore_pressure && !split) {  // (pore pressure runs on one rank)
    const Vector& p = info->grid_pore_pressure();
    return {du, mass, VtkField{"pore_pressure", 1, std::vector<double>(p.data(), p.data() + p.size())}};
  }
  return {du, mass};
}

template <int dim>
std::string grid_vtu(const Model<dim>& m, const std::vector<VtkField>& fields) {
  if (m.rank_boxes.empty()) return vtu_grid<dim>(m.grid, fields);
  const std::vector<int> keys = piece_cells(m);
  return vtu_grid<dim>(m.grid, fields, &keys);
}

template class PointColumns<1>;
template class PointColumns<2>;
template class PointColumns<3>;
template std::vector<std::string> vtu_point_columns<1>(const PointColumns<1>&);
template std::vector<std::string> vtu_point_columns<2>(const PointColumns<2>&);
template std::vector<std::string> vtu_point_columns<3>(const PointColumns<3>&);
template std::vector<VtkField> grid_vtk_fields<1>(const Model<1>&, const StepInfo*);
template std::string grid_vtu<1>(const Model<1>&, const std::vector<VtkField>&);
template std::vector<VtkField> grid_vtk_fields<2>(const Model<2>&, const StepInfo*);
template std::string grid_vtu<2>(const Model<2>&, const std::vector<VtkField>&);
template std::vector<VtkField> grid_vtk_fields<3>(const Model<3>&, const StepInfo*);
template std::string grid_vtu<3>(const Model<3>&, const std::vector<VtkField>&);

}  // namespace gradmpm
