#pragma once
// A body given by a mesh (`[[bodies]] mesh = "FILE.msh"`, docs/geometry.md): the linear
// elements of the case's dimension in one physical group of a gmsh file (or all of them),
// split into simplices: a triangle, a quadrangle as two triangles, a tetrahedron, a
// hexahedron as six tetrahedra about its 0-6 diagonal. It answers "inside?" through a
// bucket grid over its bounding box, and gives its volume. Meshes that would give a wrong
// body are refused: an unknown physical name, elements of another order or kind, an
// inverted or non-convex element, a 2D mesh off its plane.
#include <array>
#include <string>
#include <vector>

#include "gradmpm/core/Types.hpp"
#include "gradmpm/geometry/GmshMesh.hpp"

namespace gradmpm {

template <int dim>
class MeshBody {
 public:
  /// `physical`: the name of a physical group of dimension dim; empty: every element of
  /// dimension dim. `quadrature`: also keep the elements' quadrature points
  /// (quadrature()). Throws InputError naming the file and what is wrong.
  MeshBody(const GmshMesh& mesh, const std::string& physical, bool quadrature = false);

  /// A quadrature point of an element: where, and the volume it stands for.
  struct QuadraturePoint {
    Vec<dim> x;
    double weight;
  };
  /// The elements' quadrature points, whose weights add up to their volumes: 3 per
  /// triangle and 4 per tetrahedron (the symmetric interior rules, exact for linear
  /// fields), 2^dim per quadrangle and hexahedron (Gauss on the bilinear or trilinear map,
  /// whose Jacobian it integrates exactly). Empty unless asked for.
  const std::vector<QuadraturePoint>& quadrature() const { return quadrature_; }

  /// Whether x lies in an element (boundaries included, to 1e-12 of the element's size).
  bool contains(const Vec<dim>& x) const;
  const Vec<dim>& lo() const { return lo_; }
  const Vec<dim>& hi() const { return hi_; }
  /// The elements' total length / area / volume.
  double volume() const { return volume_; }
  int elements() const { return elements_; }
  int simplices() const { return static_cast<int>(simplices_.size()); }

 private:
  using Simplex = std::array<Vec<dim>, dim + 1>;
  void add_element(const GmshMesh& mesh, const GmshMesh::Block& block, int e);
  void add_simplex(const Simplex& s, long long tag, const std::string& file);
  void build_buckets();
  bool in_simplex(const Simplex& s, const Vec<dim>& x) const;

  void add_quadrature(int type, const std::array<Vec<dim>, 8>& x);

  bool keep_quadrature_ = false;
  std::vector<QuadraturePoint> quadrature_;
  std::vector<Simplex> simplices_;
  std::vector<double> sizes_;  ///< each simplex's volume
  int elements_ = 0;
  double volume_ = 0.0;
  int orientation_ = 0;  ///< 2D: the sign of the elements' areas (a mesh may wind either way)
  Vec<dim> lo_, hi_;
  // The bucket grid: the simplices overlapping each bucket (CSR).
  Vec<dim> bucket_size_;
  std::array<int, dim> buckets_{};
  std::vector<int> bucket_start_, bucket_simplices_;
};

}  // namespace gradmpm
