#include "gradmpm/io/Vtk.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <iterator>
#include <stdexcept>

namespace gradmpm {

namespace {
void header(std::string& s, std::size_t points, std::size_t cells) {
  s += "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
       "header_type=\"UInt64\">\n<UnstructuredGrid>\n";
  fmt::format_to(std::back_inserter(s), "<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", points, cells);
}

void coordinates(std::string& s, const std::vector<double>& xyz) {
  s += "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (double v : xyz) fmt::format_to(std::back_inserter(s), "{} ", v);
  s += "\n</DataArray>\n</Points>\n";
}

void cells(std::string& s, const std::vector<long>& connectivity, int per_cell, int vtk_type) {
  const std::size_t n = connectivity.size() / per_cell;
  s += "<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (long c : connectivity) fmt::format_to(std::back_inserter(s), "{} ", c);
  s += "\n</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (std::size_t i = 1; i <= n; ++i) fmt::format_to(std::back_inserter(s), "{} ", i * per_cell);
  s += "\n</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < n; ++i) fmt::format_to(std::back_inserter(s), "{} ", vtk_type);
  s += "\n</DataArray>\n</Cells>\n";
}

void point_data(std::string& s, const std::vector<VtkField>& fields, std::size_t n) {
  s += "<PointData>\n";
  for (const auto& f : fields) {
    if (f.values.size() != n * f.components) throw std::logic_error("VTK field " + f.name + " has the wrong size");
    fmt::format_to(std::back_inserter(s),
                   "<DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"ascii\">\n",
                   f.integer ? "Int64" : "Float64", f.name, f.components);
    for (double v : f.values) {
      if (f.integer)
        fmt::format_to(std::back_inserter(s), "{} ", static_cast<long long>(v));
      else
        fmt::format_to(std::back_inserter(s), "{} ", v);
    }
    s += "\n</DataArray>\n";
  }
  s += "</PointData>\n";
}

void footer(std::string& s) { s += "</Piece>\n</UnstructuredGrid>\n</VTKFile>\n"; }
}  // namespace

std::string vtu_points(const std::vector<double>& xyz, const std::vector<VtkField>& fields) {
  const std::size_t n = xyz.size() / 3;
  std::string s;
  header(s, n, n);
  coordinates(s, xyz);
  std::vector<long> conn(n);
  for (std::size_t i = 0; i < n; ++i) conn[i] = static_cast<long>(i);
  cells(s, conn, 1, 1);  // VTK_VERTEX
  point_data(s, fields, n);
  footer(s);
  return s;
}

template <int dim>
std::vector<int> cell_corners(const Grid<dim>& grid, const std::vector<int>& keys) {
  std::vector<int> nodes;
  nodes.reserve(keys.size() << dim);
  for (const int key : keys) {
    const typename Grid<dim>::Index c = grid.node_ijk(key);
    for (int k = 0; k < (1 << dim); ++k) {
      typename Grid<dim>::Index ijk;
      for (int d = 0; d < dim; ++d) ijk[d] = c[d] + ((k >> d) & 1);
      nodes.push_back(grid.node_index(ijk));
    }
  }
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  return nodes;
}

template <int dim>
std::string vtu_grid(const Grid<dim>& grid, const std::vector<VtkField>& fields, const std::vector<int>* keys) {
  std::vector<int> every;
  if (!keys) {
    for (int key = 0; key < grid.num_nodes(); ++key)
      if (grid.is_cell_key(key)) every.push_back(key);
    keys = &every;
  }
  // The cells of the keys, in that order, and their corners in VTK order: line (0,1);
  // quad (00,10,11,01); hexahedron bottom then top.
  static constexpr int order[3][8] = {{0, 1}, {0, 1, 3, 2}, {0, 1, 3, 2, 4, 5, 7, 6}};
  constexpr int corners = 1 << dim;
  // The piece's points: the corners, ascending (the whole grid: every node, in order).
  const std::vector<int> nodes = cell_corners(grid, *keys);
  std::vector<long> conn;
  for (const int key : *keys) {
    const typename Grid<dim>::Index c = grid.node_ijk(key);
    for (int k = 0; k < corners; ++k) {
      const int bits = order[dim - 1][k];
      typename Grid<dim>::Index ijk;
      for (int d = 0; d < dim; ++d) ijk[d] = c[d] + ((bits >> d) & 1);
      conn.push_back(std::lower_bound(nodes.begin(), nodes.end(), grid.node_index(ijk)) - nodes.begin());
    }
  }
  std::vector<double> xyz;
  for (const long n : nodes) {
    const Vec<dim> x = grid.node_position(static_cast<int>(n));
    for (int d = 0; d < 3; ++d) xyz.push_back(d < dim ? x[d] : 0.0);
  }
  std::vector<VtkField> at_nodes;
  for (const auto& f : fields) {
    if (f.values.size() == nodes.size() * f.components) {  // at the piece's points already
      at_nodes.push_back(f);
      continue;
    }
    if (f.values.size() != static_cast<std::size_t>(grid.num_nodes()) * f.components)
      throw std::logic_error("VTK grid field " + f.name + " needs values at every grid node or at the piece's points");
    VtkField g{f.name, f.components, {}, f.integer};
    g.values.reserve(nodes.size() * f.components);
    for (const long n : nodes)
      for (int k = 0; k < f.components; ++k) g.values.push_back(f.values[n * f.components + k]);
    at_nodes.push_back(std::move(g));
  }
  std::string s;
  header(s, nodes.size(), conn.size() / corners);
  coordinates(s, xyz);
  cells(s, conn, corners, dim == 1 ? 3 : (dim == 2 ? 9 : 12));
  point_data(s, at_nodes, nodes.size());
  footer(s);
  return s;
}

template std::vector<int> cell_corners<1>(const Grid<1>&, const std::vector<int>&);
template std::vector<int> cell_corners<2>(const Grid<2>&, const std::vector<int>&);
template std::vector<int> cell_corners<3>(const Grid<3>&, const std::vector<int>&);
template std::string vtu_grid<1>(const Grid<1>&, const std::vector<VtkField>&, const std::vector<int>*);
template std::string vtu_grid<2>(const Grid<2>&, const std::vector<VtkField>&, const std::vector<int>*);
template std::string vtu_grid<3>(const Grid<3>&, const std::vector<VtkField>&, const std::vector<int>*);

std::string pvtu(const std::vector<VtkField>& layout, const std::vector<std::string>& pieces) {
  std::string s =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
      "header_type=\"UInt64\">\n<PUnstructuredGrid GhostLevel=\"0\">\n<PPointData>\n";
  for (const auto& f : layout)
    fmt::format_to(std::back_inserter(s), "<PDataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\"/>\n",
                   f.integer ? "Int64" : "Float64", f.name, f.components);
  s += "</PPointData>\n<PPoints>\n<PDataArray type=\"Float64\" NumberOfComponents=\"3\"/>\n</PPoints>\n";
  for (const auto& piece : pieces) fmt::format_to(std::back_inserter(s), "<Piece Source=\"{}\"/>\n", piece);
  s += "</PUnstructuredGrid>\n</VTKFile>\n";
  return s;
}

std::string pvd(const std::vector<std::pair<double, std::string>>& entries) {
  std::string s =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\" "
      "byte_order=\"LittleEndian\">\n<Collection>\n";
  for (const auto& [t, file] : entries)
    fmt::format_to(std::back_inserter(s), "<DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{}\"/>\n", t, file);
  s += "</Collection>\n</VTKFile>\n";
  return s;
}

}  // namespace gradmpm
