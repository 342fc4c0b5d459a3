#include "gradmpm/geometry/MeshBody.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "gradmpm/core/Errors.hpp"

namespace gradmpm {

namespace {

/// The signed measure of a simplex: a triangle's area (positive counter-clockwise), a
/// tetrahedron's volume (positive for gmsh's node order).
template <int dim>
double signed_measure(const std::array<Vec<dim>, dim + 1>& s) {
  Eigen::Matrix<double, dim, dim> J;
  for (int i = 0; i < dim; ++i) J.col(i) = s[i + 1] - s[0];
  return J.determinant() / (dim == 2 ? 2.0 : 6.0);
}

/// The simplices an element splits into, as corner numbers: a quadrangle into two
/// triangles (exact for the convex quadrangles a valid mesh has), a hexahedron into six
/// tetrahedra about its 0-6 diagonal (gmsh's node order: 0-3 the bottom face, 4-7 the top).
const std::vector<std::vector<int>>& split_of(int type) {
  static const std::vector<std::vector<int>> triangle{{0, 1, 2}}, quadrangle{{0, 1, 2}, {0, 2, 3}},
      tetrahedron{{0, 1, 2, 3}},
      hexahedron{{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6}, {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
  static const std::vector<std::vector<int>> none;
  switch (type) {
    case 2: return triangle;
    case 3: return quadrangle;
    case 4: return tetrahedron;
    case 5: return hexahedron;
    default: return none;
  }
}

bool linear_of_dim(int type, int dim) { return dim == 2 ? (type == 2 || type == 3) : (type == 4 || type == 5); }

}  // namespace

template <int dim>
MeshBody<dim>::MeshBody(const GmshMesh& mesh, const std::string& physical, bool quadrature)
    : keep_quadrature_(quadrature) {
  static_assert(dim == 2 || dim == 3, "mesh bodies are 2D or 3D");
  int tag = -1;  // the physical group's tag
  if (!physical.empty()) {
    std::vector<std::string> known;
    for (const auto& p : mesh.names) {
      if (p.dim == dim && p.name == physical) tag = p.tag;
      if (p.dim == dim) known.push_back("\"" + p.name + "\"");
    }
    if (tag < 0)
      throw InputError(fmt::format("{}: no {}D physical group \"{}\" ({})", mesh.file, dim, physical,
                                   known.empty() ? std::string("the file names none")
                                                 : fmt::format("it has {}", fmt::join(known, ", "))));
  }
  lo_.setConstant(std::numeric_limits<double>::max());
  hi_.setConstant(std::numeric_limits<double>::lowest());
  for (const GmshMesh::Block& block : mesh.blocks) {
    if (block.dim != dim) continue;  // (boundaries: lines, faces, points)
    if (tag >= 0) {
      const auto found = mesh.entity_physicals.find({block.dim, block.entity});
      if (found == mesh.entity_physicals.end() ||
          std::find(found->second.begin(), found->second.end(), tag) == found->second.end())
        continue;
    }
    if (!linear_of_dim(block.type, dim))
      throw InputError(fmt::format(
          "{}: element {} is a {}; a {}D body takes linear {} (gmsh -order 1)", mesh.file, block.tags.front(),
          gmsh_element_name(block.type), dim, dim == 2 ? "triangles and quadrangles" : "tetrahedra and hexahedra"));
    for (int e = 0; e < block.count(); ++e) add_element(mesh, block, e);
  }
  if (elements_ == 0)
    throw InputError(fmt::format("{}: no {}D elements{}", mesh.file, dim,
                                 physical.empty() ? std::string() : fmt::format(" in physical group \"{}\"", physical)));
  build_buckets();
}

template <int dim>
void MeshBody<dim>::add_element(const GmshMesh& mesh, const GmshMesh::Block& block, int e) {
  const long long tag = block.tags[e];
  std::array<Vec<dim>, 8> x;
  for (int a = 0; a < block.per; ++a) {
    const auto& c = mesh.coordinates[block.nodes[static_cast<std::size_t>(e) * block.per + a]];
    for (int d = 0; d < dim; ++d) x[a][d] = c[d];
    if (dim == 2 && std::abs(c[2] - mesh.coordinates[block.nodes[0]][2]) > 1e-9 * (1.0 + std::abs(c[0]) + std::abs(c[1])))
      throw InputError(fmt::format("{}: element {} leaves the plane z = {} of the 2D mesh (a 2D body is a plane mesh)",
                                   mesh.file, tag, mesh.coordinates[block.nodes[0]][2]));
    lo_ = lo_.cwiseMin(x[a]);
    hi_ = hi_.cwiseMax(x[a]);
  }
  if constexpr (dim == 2)
    if (block.type == 3) {  // its two triangles cover a quadrangle only where it is convex: each corner turns alike
      double area = 0.0;    // (the shoelace: its winding)
      for (int a = 0; a < 4; ++a) area += x[a][0] * x[(a + 1) % 4][1] - x[(a + 1) % 4][0] * x[a][1];
      for (int a = 0; a < 4; ++a) {
        const Simplex corner{x[(a + 3) % 4], x[a], x[(a + 1) % 4]};
        if (signed_measure<dim>(corner) * area <= 0.0)
          throw InputError(fmt::format("{}: element {} is not convex (its corner {} turns the other way)", mesh.file,
                                       tag, a + 1));
      }
    }
  for (const auto& corners : split_of(block.type)) {
    Simplex s;
    for (int i = 0; i <= dim; ++i) s[i] = x[corners[i]];
    add_simplex(s, tag, mesh.file);
  }
  if (keep_quadrature_) add_quadrature(block.type, x);
  ++elements_;
}

template <int dim>
void MeshBody<dim>::add_quadrature(int type, const std::array<Vec<dim>, 8>& x) {
  if (type == 2 || type == 4) {  // the symmetric interior rule of a simplex: dim + 1 points of equal weight
    const double a = dim == 2 ? 2.0 / 3.0 : 0.5854101966249685, b = dim == 2 ? 1.0 / 6.0 : 0.1381966011250105;
    Simplex s;
    for (int i = 0; i <= dim; ++i) s[i] = x[i];
    const double w = std::abs(signed_measure<dim>(s)) / (dim + 1);
    for (int i = 0; i <= dim; ++i) {
      Vec<dim> p = Vec<dim>::Zero();
      for (int j = 0; j <= dim; ++j) p += (i == j ? a : b) * x[j];
      quadrature_.push_back({p, w});
    }
    return;
  }
  // Gauss, 2 points per direction, on the (bi/tri)linear map of the reference cube [-1, 1]^dim
  // (gmsh's corner order: counter-clockwise in the plane, the bottom face before the top).
  static const int sign[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                 {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  const int corners = 1 << dim;
  const double g = 1.0 / std::sqrt(3.0);
  for (int q = 0; q < corners; ++q) {
    double xi[3];
    for (int d = 0; d < dim; ++d) xi[d] = sign[q][d] * g;
    Vec<dim> p = Vec<dim>::Zero();
    Eigen::Matrix<double, dim, dim> J = Eigen::Matrix<double, dim, dim>::Zero();  // dx / dxi
    for (int a = 0; a < corners; ++a) {
      double N = 1.0 / corners;
      for (int d = 0; d < dim; ++d) N *= 1.0 + sign[a][d] * xi[d];
      p += N * x[a];
      for (int k = 0; k < dim; ++k) {
        double dN = sign[a][k] / static_cast<double>(corners);
        for (int d = 0; d < dim; ++d)
          if (d != k) dN *= 1.0 + sign[a][d] * xi[d];
        J.col(k) += dN * x[a];
      }
    }
    quadrature_.push_back({p, std::abs(J.determinant())});
  }
}

template <int dim>
void MeshBody<dim>::add_simplex(const Simplex& s, long long tag, const std::string& file) {
  const double v = signed_measure<dim>(s);
  double extent = 0.0;
  for (int i = 1; i <= dim; ++i) extent = std::max(extent, (s[i] - s[0]).norm());
  const double degenerate = 1e-12 * std::pow(extent, dim);
  const int sign = v > degenerate ? 1 : (v < -degenerate ? -1 : 0);
  if (sign == 0)
    throw InputError(fmt::format("{}: element {} has no {} (its corners are in line{})", file, tag,
                                 dim == 2 ? "area" : "volume", dim == 2 ? "" : " or in one plane"));
  // 2D: a surface meshed with its normal along -z winds clockwise, and is as good; the
  // elements of one body wind alike. 3D: gmsh orders a valid element's nodes positively.
  if (dim == 3 && sign < 0)
    throw InputError(fmt::format("{}: element {} is inverted or not convex (a part of it has negative volume)", file, tag));
  if (dim == 2) {
    if (orientation_ == 0) orientation_ = sign;
    if (sign != orientation_)
      throw InputError(fmt::format("{}: element {} is inverted or not convex (it winds the other way round from the "
                                   "body's first element)",
                                   file, tag));
  }
  simplices_.push_back(s);
  sizes_.push_back(std::abs(v));
  volume_ += std::abs(v);
}

template <int dim>
void MeshBody<dim>::build_buckets() {
  // About one simplex per bucket: a bucket's side is the mean simplex's.
  const Vec<dim> extent = (hi_ - lo_).cwiseMax(1e-300);
  const double side = std::pow(volume_ / static_cast<double>(simplices_.size()), 1.0 / dim);
  long long total = 1;
  for (int d = 0; d < dim; ++d) {
    buckets_[d] = static_cast<int>(std::clamp(std::ceil(extent[d] / side), 1.0, 4096.0));
    bucket_size_[d] = extent[d] / buckets_[d];
    total *= buckets_[d];
  }
  std::vector<int> count(static_cast<std::size_t>(total) + 1, 0);
  auto each_bucket = [&](const Simplex& s, auto&& f) {
    std::array<int, dim> first, last;
    for (int d = 0; d < dim; ++d) {
      double a = s[0][d], b = s[0][d];
      for (const auto& x : s) {
        a = std::min(a, x[d]);
        b = std::max(b, x[d]);
      }
      first[d] = std::clamp(static_cast<int>(std::floor((a - lo_[d]) / bucket_size_[d])), 0, buckets_[d] - 1);
      last[d] = std::clamp(static_cast<int>(std::floor((b - lo_[d]) / bucket_size_[d])), 0, buckets_[d] - 1);
    }
    std::array<int, dim> i = first;
    while (true) {
      long long key = 0;
      for (int d = dim - 1; d >= 0; --d) key = key * buckets_[d] + i[d];
      f(static_cast<std::size_t>(key));
      int d = 0;  // the next bucket: an odometer over first..last
      for (; d < dim; ++d) {
        if (++i[d] <= last[d]) break;
        i[d] = first[d];
      }
      if (d == dim) break;
    }
  };
  for (const Simplex& s : simplices_) each_bucket(s, [&](std::size_t key) { ++count[key + 1]; });
  for (std::size_t k = 1; k < count.size(); ++k) count[k] += count[k - 1];
  bucket_start_ = count;
  bucket_simplices_.resize(static_cast<std::size_t>(count.back()));
  for (std::size_t j = 0; j < simplices_.size(); ++j)
    each_bucket(simplices_[j], [&](std::size_t key) { bucket_simplices_[count[key]++] = static_cast<int>(j); });
}

template <int dim>
bool MeshBody<dim>::in_simplex(const Simplex& s, const Vec<dim>& x) const {
  // Barycentric coordinates: x = s0 + J lambda, every lambda_i and 1 - sum >= -tol.
  Eigen::Matrix<double, dim, dim> J;
  for (int i = 0; i < dim; ++i) J.col(i) = s[i + 1] - s[0];
  const Vec<dim> l = J.partialPivLu().solve(x - s[0]);
  constexpr double tol = 1e-12;
  return l.minCoeff() >= -tol && l.sum() <= 1.0 + tol;
}

template <int dim>
bool MeshBody<dim>::contains(const Vec<dim>& x) const {
  std::array<int, dim> i;
  for (int d = 0; d < dim; ++d) {
    const double tol = 1e-12 * (hi_[d] - lo_[d]);
    if (x[d] < lo_[d] - tol || x[d] > hi_[d] + tol) return false;
    i[d] = std::clamp(static_cast<int>(std::floor((x[d] - lo_[d]) / bucket_size_[d])), 0, buckets_[d] - 1);
  }
  long long key = 0;
  for (int d = dim - 1; d >= 0; --d) key = key * buckets_[d] + i[d];
  for (int k = bucket_start_[key]; k < bucket_start_[key + 1]; ++k)
    if (in_simplex(simplices_[bucket_simplices_[k]], x)) return true;
  return false;
}

template class MeshBody<2>;
template class MeshBody<3>;

}  // namespace gradmpm
