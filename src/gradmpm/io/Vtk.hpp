#pragma once
// ParaView-readable VTK XML: unstructured grids (.vtu) for material points (vertex
// cells) and for the background grid (lines, quads or hexahedra), and .pvd collections
// that index them by load factor. ASCII, so the files can be inspected and diffed.
#include <string>
#include <utility>
#include <vector>

#include "gradmpm/grid/Grid.hpp"

namespace gradmpm {

struct VtkField {
  std::string name;
  int components = 1;          ///< 1 scalar, 3 vector, 9 tensor (row-major)
  std::vector<double> values;  ///< size = n * components
  bool integer = false;        ///< written as Int64
};

/// Points as VTK_VERTEX cells; `xyz` has 3 coordinates per point.
std::string vtu_points(const std::vector<double>& xyz, const std::vector<VtkField>& fields);

/// The corners of the cells whose lower-corner nodes (keys) are `keys`, ascending: a
/// grid piece's points.
template <int dim>
std::vector<int> cell_corners(const Grid<dim>& grid, const std::vector<int>& keys);

/// The background grid's cells whose lower-corner nodes (keys) are `keys`, ascending (a
/// distributed run's piece: its box of Model::rank_boxes; null: every cell) with their
/// corners, ascending (cell_corners), as the piece's points. `fields` are nodal
/// (PointData), given at every grid node (the piece takes its corners' values) or at the
/// piece's points only, in their order.
template <int dim>
std::string vtu_grid(const Grid<dim>& grid, const std::vector<VtkField>& fields,
                     const std::vector<int>* keys = nullptr);

/// A parallel file (.pvtu) of pieces written by vtu_points or vtu_grid, one per rank:
/// the fields' names, components and types (`layout`; values unused) and the pieces'
/// file names relative to the .pvtu.
std::string pvtu(const std::vector<VtkField>& layout, const std::vector<std::string>& pieces);

/// A collection: (load factor, file name relative to the .pvd).
std::string pvd(const std::vector<std::pair<double, std::string>>& entries);

}  // namespace gradmpm
