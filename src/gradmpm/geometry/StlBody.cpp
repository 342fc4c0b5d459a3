#include "gradmpm/geometry/StlBody.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "gradmpm/core/Errors.hpp"

namespace gradmpm {

namespace fs = std::filesystem;

namespace {

using Triangle = std::array<Eigen::Vector3d, 3>;

std::string point_text(const Eigen::Vector3d& p) { return fmt::format("({:g}, {:g}, {:g})", p[0], p[1], p[2]); }

std::vector<Triangle> read_binary(const std::string& bytes, const fs::path& file) {
  std::uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, 4);
  std::vector<Triangle> out(count);
  for (std::uint32_t t = 0; t < count; ++t) {
    const char* at = bytes.data() + 84 + 50 * static_cast<std::size_t>(t) + 12;  // (after the normal)
    for (int v = 0; v < 3; ++v)
      for (int d = 0; d < 3; ++d) {
        float x = 0.0f;
        std::memcpy(&x, at + 12 * v + 4 * d, 4);
        if (!std::isfinite(x))
          throw InputError(fmt::format("{}: triangle {}: a coordinate that is not a finite number", file.string(), t));
        out[t][v][d] = x;
      }
  }
  return out;
}

std::vector<Triangle> read_ascii(const std::string& text, const fs::path& file) {
  std::istringstream in(text);
  std::vector<Triangle> out;
  Triangle t;
  int vertices = -1;  // in the current loop; -1 outside one
  int number = 0;
  const auto fail = [&](const std::string& what) {
    throw InputError(fmt::format("{}:{}: {}", file.string(), number, what));
  };
  for (std::string line; std::getline(in, line);) {
    ++number;
    std::istringstream words(line);
    std::string word;
    if (!(words >> word)) continue;
    if (word == "outer") {
      vertices = 0;
    } else if (word == "vertex") {
      if (vertices < 0 || vertices > 2) fail("a vertex outside a loop of three");
      Eigen::Vector3d p;
      if (!(words >> p[0] >> p[1] >> p[2]) || !p.allFinite()) fail("expected \"vertex x y z\"");
      t[vertices++] = p;
    } else if (word == "endloop") {
      if (vertices != 3) fail("a loop without three vertices");
      out.push_back(t);
      vertices = -1;
    } else if (word != "solid" && word != "facet" && word != "endfacet" && word != "endsolid") {
      fail(fmt::format("unexpected \"{}\"", word));
    }
  }
  return out;
}

/// Twice the signed area of (a, b, q) in the y-z plane, computed from the edge's vertices in
/// one order whichever way it is passed, so that the two triangles sharing an edge see the
/// same value with opposite signs.
double orient(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& q) {
  const bool swap = b[0] < a[0] || (b[0] == a[0] && b[1] < a[1]);
  const Eigen::Vector2d& p0 = swap ? b : a;
  const Eigen::Vector2d& p1 = swap ? a : b;
  const double v = (p1[0] - p0[0]) * (q[1] - p0[1]) - (p1[1] - p0[1]) * (q[0] - p0[0]);
  return swap ? -v : v;
}

/// The top-left rule: edge a -> b of a counter-clockwise triangle owns the points on it
/// when it runs down, or along the u axis backwards; its reverse never does, so a shared
/// edge belongs to one triangle.
bool owns(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return b[1] < a[1] || (b[1] == a[1] && b[0] < a[0]); }

}  // namespace

std::vector<Triangle> read_stl(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open the STL file", file.string()));
  std::ostringstream s;
  s << in.rdbuf();
  const std::string bytes = s.str();
  // Binary when the header's count matches the size (some binary files start "solid" too).
  if (bytes.size() >= 84) {
    std::uint32_t count = 0;
    std::memcpy(&count, bytes.data() + 80, 4);
    if (bytes.size() == 84 + 50 * static_cast<std::size_t>(count)) return read_binary(bytes, file);
  }
  if (bytes.compare(0, 5, "solid") != 0)
    throw InputError(fmt::format("{}: not an STL file (neither \"solid\" text nor a binary file of its count's size)",
                                 file.string()));
  return read_ascii(bytes, file);
}

StlBody::StlBody(const fs::path& file) : triangles_(read_stl(file)) {
  if (triangles_.size() < 4)
    throw InputError(fmt::format("{}: {} triangle(s); a closed surface has at least 4", file.string(),
                                 triangles_.size()));
  lo_.setConstant(std::numeric_limits<double>::max());
  hi_.setConstant(std::numeric_limits<double>::lowest());
  for (const Triangle& t : triangles_) {
    if ((t[1] - t[0]).cross(t[2] - t[0]).norm() == 0.0)
      throw InputError(fmt::format("{}: a degenerate triangle {} {} {} (no area)", file.string(), point_text(t[0]),
                                   point_text(t[1]), point_text(t[2])));
    for (const auto& p : t) {
      lo_ = lo_.cwiseMin(p);
      hi_ = hi_.cwiseMax(p);
    }
    volume_ += t[0].dot(t[1].cross(t[2])) / 6.0;
  }
  volume_ = std::abs(volume_);  // (inward normals: the same body)
  check_closed(file);
  build_buckets();
}

void StlBody::check_closed(const fs::path& file) const {
  using Key = std::array<double, 6>;
  std::map<Key, int> directed;  // a -> b: how many triangles run along it that way
  const auto key = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return Key{a[0], a[1], a[2], b[0], b[1], b[2]};
  };
  for (const Triangle& t : triangles_)
    for (int e = 0; e < 3; ++e) ++directed[key(t[e], t[(e + 1) % 3])];
  for (const auto& [k, n] : directed) {
    const Eigen::Vector3d a(k[0], k[1], k[2]), b(k[3], k[4], k[5]);
    const auto back = directed.find(key(b, a));
    const int reverse = back == directed.end() ? 0 : back->second;
    if (n > 1)
      throw InputError(fmt::format("{}: the triangles are not oriented alike: {} run from {} to {} the same way",
                                   file.string(), n, point_text(a), point_text(b)));
    if (reverse != 1)
      throw InputError(fmt::format("{}: not a closed surface: the edge {} - {} belongs to {} triangle(s), not 2",
                                   file.string(), point_text(a), point_text(b), n + reverse));
  }
}

void StlBody::build_buckets() {
  const int side = std::max(1, static_cast<int>(std::sqrt(triangles_.size() / 2.0)));
  for (int d = 0; d < 2; ++d) {
    nb_[d] = side;
    b0_[d] = lo_[d + 1];
    bh_[d] = std::max((hi_[d + 1] - lo_[d + 1]) / side, 1e-300);
  }
  buckets_.assign(static_cast<std::size_t>(nb_[0]) * nb_[1], {});
  for (int t = 0; t < static_cast<int>(triangles_.size()); ++t) {
    int first[2], last[2];
    for (int d = 0; d < 2; ++d) {
      double a = triangles_[t][0][d + 1], b = a;
      for (const auto& p : triangles_[t]) {
        a = std::min(a, p[d + 1]);
        b = std::max(b, p[d + 1]);
      }
      first[d] = std::clamp(static_cast<int>(std::floor((a - b0_[d]) / bh_[d])), 0, nb_[d] - 1);
      last[d] = std::clamp(static_cast<int>(std::floor((b - b0_[d]) / bh_[d])), 0, nb_[d] - 1);
    }
    for (int i = first[0]; i <= last[0]; ++i)
      for (int j = first[1]; j <= last[1]; ++j) buckets_[static_cast<std::size_t>(i) * nb_[1] + j].push_back(t);
  }
}

int StlBody::crossing(const Triangle& t, const Eigen::Vector3d& x) const {
  std::array<Eigen::Vector2d, 3> p = {Eigen::Vector2d(t[0][1], t[0][2]), Eigen::Vector2d(t[1][1], t[1][2]),
                                      Eigen::Vector2d(t[2][1], t[2][2])};
  std::array<double, 3> xs = {t[0][0], t[1][0], t[2][0]};
  const double area = orient(p[0], p[1], p[2]);
  if (area == 0.0) return 0;  // edge-on to the ray
  if (area < 0.0) {           // counter-clockwise in y-z
    std::swap(p[1], p[2]);
    std::swap(xs[1], xs[2]);
  }
  const Eigen::Vector2d q(x[1], x[2]);
  std::array<double, 3> w;  // w_i: against the edge opposite vertex i
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector2d &a = p[(i + 1) % 3], &b = p[(i + 2) % 3];
    w[i] = orient(a, b, q);
    if (w[i] < 0.0 || (w[i] == 0.0 && !owns(a, b))) return 0;
  }
  const double sum = w[0] + w[1] + w[2];
  const double hit = (w[0] * xs[0] + w[1] * xs[1] + w[2] * xs[2]) / sum;
  return hit > x[0] ? 1 : 0;
}

bool StlBody::contains(const Eigen::Vector3d& x) const {
  for (int d = 0; d < 3; ++d)
    if (x[d] < lo_[d] || x[d] > hi_[d]) return false;
  const int i = std::clamp(static_cast<int>(std::floor((x[1] - b0_[0]) / bh_[0])), 0, nb_[0] - 1);
  const int j = std::clamp(static_cast<int>(std::floor((x[2] - b0_[1]) / bh_[1])), 0, nb_[1] - 1);
  int crossings = 0;
  for (const int t : buckets_[static_cast<std::size_t>(i) * nb_[1] + j]) crossings += crossing(triangles_[t], x);
  return crossings % 2 == 1;
}

}  // namespace gradmpm
