#pragma once
// A 3D body bounded by a closed triangulated surface (`[[bodies]] stl = "FILE.stl"`,
// docs/geometry.md), read from STL, ASCII or binary. The surface must be closed and
// consistently oriented: every edge is shared by exactly two triangles, which run along it
// in opposite directions; otherwise it is refused, naming the file and an edge. "Inside?"
// is the parity of the surface's crossings by the ray from the point along +x. The
// triangles are projected on the y-z plane and a crossing is counted where the point's
// projection falls in a triangle's. A projection on a shared edge or vertex counts for one
// triangle only, by the top-left rule of rasterisation, so a ray through an edge is one
// crossing, not two. A triangle edge-on to the ray (zero projected area) is never crossed.
// A bucket grid over y-z holds the triangles each ray can meet.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <filesystem>
#include <vector>

namespace gradmpm {

class StlBody {
 public:
  /// Reads and checks `file`; throws InputError "FILE: what is wrong".
  explicit StlBody(const std::filesystem::path& file);

  /// Whether x lies inside the surface (a point on it: either).
  bool contains(const Eigen::Vector3d& x) const;
  const Eigen::Vector3d& lo() const { return lo_; }
  const Eigen::Vector3d& hi() const { return hi_; }
  /// The enclosed volume (the divergence theorem over the triangles).
  double volume() const { return volume_; }
  int triangles() const { return static_cast<int>(triangles_.size()); }

 private:
  using Triangle = std::array<Eigen::Vector3d, 3>;
  void check_closed(const std::filesystem::path& file) const;
  void build_buckets();
  /// +1 where the ray from x along +x crosses triangle t, else 0.
  int crossing(const Triangle& t, const Eigen::Vector3d& x) const;

  std::vector<Triangle> triangles_;
  Eigen::Vector3d lo_, hi_;
  double volume_ = 0.0;
  int nb_[2] = {1, 1};                      ///< buckets along y, z
  double b0_[2] = {0, 0}, bh_[2] = {1, 1};  ///< the buckets' origin and size in y, z
  std::vector<std::vector<int>> buckets_;   ///< triangles whose y-z box meets each bucket
};

/// The triangles of an STL file, ASCII ("solid ...") or binary (80-byte header, count, 50
/// bytes per triangle); throws InputError "FILE: what is wrong" (FILE:LINE in ASCII).
std::vector<std::array<Eigen::Vector3d, 3>> read_stl(const std::filesystem::path& file);

}  // namespace gradmpm
