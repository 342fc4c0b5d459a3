// Requirements on bodies from meshes (geometry/GmshMesh.hpp, geometry/MeshBody.hpp,
// `[[bodies]] mesh`, docs/geometry.md):
//  G1 a gmsh MSH 4.1 file is read: the elements of a physical group make the body, their
//     areas and volumes add up to the group's (to 1e-15), and "inside?" holds in its
//     elements and not beside them; the lower-dimensional elements are left out;
//  G2 a mesh that would give a wrong body is refused with one line naming the file and
//     what is wrong: another MSH version, a binary file, an unknown physical name, a
//     second-order element, an inverted or non-convex element, a node an element names but
//     the file lacks;
//  G3 a mesh body fills the grid as the box or polygon it meshes does: the same points
//     (positions, volumes) from a mesh of two squares as from the two boxes, material by
//     physical group;
//  G4 with placement = "elements" the points are the elements' quadrature points: 3 per
//     triangle, 4 per quadrangle and tetrahedron, 8 per hexahedron, inside their
//     elements, their volumes adding up to the mesh's to 1e-12 (also on the slope
//     example's gmsh mesh), their masses density times volume; with it points_per_cell
//     and a distributed run are refused;
//  G5 a polygon with holes keeps the points of the polygon outside every hole: a 4 x 4
//     square less a 2 x 2 square and a 1 x 0.5 one, their sub-cells' volumes the area 16 - 4 -
//     0.5 exactly (the edges run on sub-cell lines); a hole outside its polygon, holes
//     that overlap, and holes without a polygon are refused, naming the key;
//  G6 a 3D body bounded by an STL surface (ASCII or binary) keeps the sub-cell centres
//     inside it: a unit cube's 12 triangles give its 512 points and volume 1 exactly (rays
//     through the faces' diagonals count once), an octahedron's points converge to its
//     volume 4/3 as the cells shrink; an open surface, a flipped triangle, an STL surface
//     in 2D and one beside min/max are refused, naming the file or the key.
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <tuple>

#include "gradmpm/app/MpmCase.hpp"
#include "gradmpm/core/Errors.hpp"
#include "gradmpm/geometry/GmshMesh.hpp"
#include "gradmpm/geometry/MeshBody.hpp"
#include "gradmpm/geometry/StlBody.hpp"

using namespace gradmpm;
namespace fs = std::filesystem;

namespace {

const fs::path kMeshes = fs::path(GRADMPM_SOURCE_DIR) / "tests" / "meshes";

std::string slurp(const fs::path& f) {
  std::ifstream in(f);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// `text` written to a file of its own; the message a body of dimension `dim` from it
/// (physical group `physical`) is refused with ("" if it is not).
template <int dim>
std::string refusal(const std::string& text, const std::string& physical = "") {
  const fs::path file = fs::temp_directory_path() / fmt::format("gradmpm_geometry_{}.msh", ::getpid());
  std::ofstream(file) << text;
  try {
    MeshBody<dim> body(read_gmsh(file), physical);
  } catch (const InputError& e) {
    fs::remove(file);
    return e.what();
  }
  fs::remove(file);
  return "";
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

}  // namespace

TEST(Geometry, G1_PhysicalGroupsMakeTheBodies) {
  const GmshMesh mesh = read_gmsh(kMeshes / "two_squares.msh");
  const MeshBody<2> soil(mesh, "soil"), rock(mesh, "rock"), all(mesh, "");
  std::cout << "soil: " << soil.elements() << " elements, area " << soil.volume() << "; rock: " << rock.elements()
            << " elements, area " << rock.volume() << "; all: " << all.volume() << "\n";
  EXPECT_EQ(soil.elements(), 2);
  EXPECT_EQ(rock.elements(), 1);
  EXPECT_NEAR(soil.volume(), 1.0, 1e-15);
  EXPECT_NEAR(rock.volume(), 1.0, 1e-15);
  EXPECT_NEAR(all.volume(), 2.0, 1e-15);
  EXPECT_TRUE(soil.contains(Vec<2>(0.5, 0.5)));
  EXPECT_TRUE(soil.contains(Vec<2>(0.0, 1.0)));  // (a corner)
  EXPECT_FALSE(soil.contains(Vec<2>(1.5, 0.5)));
  EXPECT_TRUE(rock.contains(Vec<2>(1.5, 0.5)));
  EXPECT_FALSE(rock.contains(Vec<2>(2.0001, 0.5)));
  EXPECT_TRUE(all.contains(Vec<2>(1.0, 0.25)));

  const GmshMesh solid = read_gmsh(kMeshes / "cube_and_wedge.msh");
  const MeshBody<3> block(solid, "block"), wedge(solid, "wedge");
  std::cout << "block: volume " << block.volume() << " (" << block.simplices() << " tetrahedra); wedge: "
            << wedge.volume() << "\n";
  EXPECT_NEAR(block.volume(), 1.0, 1e-15);
  EXPECT_NEAR(wedge.volume(), 1.0 / 6.0, 1e-15);
  EXPECT_TRUE(block.contains(Vec<3>(0.2, 0.7, 0.9)));
  EXPECT_FALSE(block.contains(Vec<3>(0.2, 1.1, 0.9)));
  EXPECT_TRUE(wedge.contains(Vec<3>(1.2, 0.2, 0.2)));
  EXPECT_FALSE(wedge.contains(Vec<3>(1.5, 0.5, 0.5)));  // (beyond its slanted face)
}

TEST(Geometry, G2_BadMeshesAreRefusedNamingFileAndFault) {
  const std::string good = slurp(kMeshes / "two_squares.msh");
  struct Case {
    std::string what, text, physical, message;
  };
  const std::vector<Case> cases = {
      {"MSH 2.2", replaced(good, "4.1 0 8", "2.2 0 8"), "", "MSH version 2.2 (this reader takes 4.1"},
      {"binary", replaced(good, "4.1 0 8", "4.1 1 8"), "", "a binary MSH file"},
      {"unknown physical", good, "clay", "no 2D physical group \"clay\" (it has \"soil\", \"rock\")"},
      {"second order", replaced(good, "2 2 3 1\n3 2 5 6 3", "2 2 9 1\n3 2 5 6 3 1 2"), "",
       "element 3 is a second-order element (gmsh type 9); a 2D body takes linear triangles and quadrangles"},
      {"inverted triangle", replaced(good, "2 1 3 4", "2 1 4 3"), "",
       "element 2 is inverted or not convex (it winds the other way round"},
      {"non-convex quadrangle", replaced(good, "2 0 0\n2 1 0\n$EndNodes", "2 0 0\n1.2 0.2 0\n$EndNodes"), "rock",
       "element 3 is not convex (its corner 3 turns the other way)"},
      {"missing node", replaced(good, "1 1 2 3", "1 1 2 7"), "", "element 1 names node 7, which $Nodes does not hold"},
  };
  for (const Case& c : cases) {
    const std::string message = refusal<2>(c.text, c.physical);
    std::cout << c.what << ": " << message << "\n";
    EXPECT_NE(message.find(c.message), std::string::npos) << c.what << ": " << message;
    EXPECT_NE(message.find("gradmpm_geometry_"), std::string::npos) << "the file is named";
    EXPECT_EQ(message.find('\n'), std::string::npos) << "one line";
  }
}

TEST(Geometry, G3_AMeshBodyFillsTheGridAsTheShapeItMeshes) {
  const auto read = [](const std::string& bodies) {
    const std::string text = R"(
[grid]
origin = [-0.5, -0.5]
cell_size = 0.25
cells = [12, 8]
[materials.soil]
model = "linear-elastic"
young = 100.0
[materials.rock]
model = "linear-elastic"
young = 1000.0
)" + bodies + R"(
[load_steps]
count = 1
)";
    CaseFile cf = CaseFile::parse(text, (kMeshes / "case.toml").string());
    return read_mpm_case<2>(cf).model;
  };
  const Model<2> boxes = read(R"(
[[bodies]]
material = "soil"
min = [0.0, 0.0]
max = [1.0, 1.0]
[[bodies]]
material = "rock"
min = [1.0, 0.0]
max = [2.0, 1.0]
points_per_cell = 3
)");
  const Model<2> meshes = read(R"(
[[bodies]]
material = "soil"
mesh = "two_squares.msh"
physical = "soil"
[[bodies]]
material = "rock"
mesh = "two_squares.msh"
physical = "rock"
points_per_cell = 3
)");
  std::cout << "boxes: " << boxes.points.size() << " points; meshes: " << meshes.points.size() << " points\n";
  ASSERT_EQ(boxes.points.size(), meshes.points.size());
  double volume = 0.0;
  for (int p = 0; p < boxes.points.size(); ++p) {
    EXPECT_EQ(boxes.points.position[p], meshes.points.position[p]) << p;
    EXPECT_EQ(boxes.points.volume[p], meshes.points.volume[p]) << p;
    EXPECT_EQ(boxes.points.material[p], meshes.points.material[p]) << p;
    volume += meshes.points.volume[p];
  }
  EXPECT_NEAR(volume, 2.0, 1e-12);
}

TEST(Geometry, G4_ElementPlacementPutsPointsAtQuadraturePoints) {
  for (const auto& [file, physical, dim_points, volume] :
       std::vector<std::tuple<std::string, std::string, int, double>>{{"two_squares.msh", "soil", 6, 1.0},
                                                                      {"two_squares.msh", "rock", 4, 1.0}}) {
    const MeshBody<2> body(read_gmsh(kMeshes / file), physical, true);
    double sum = 0.0;
    for (const auto& q : body.quadrature()) {
      sum += q.weight;
      EXPECT_TRUE(body.contains(q.x)) << physical;
    }
    EXPECT_EQ(static_cast<int>(body.quadrature().size()), dim_points) << physical;
    EXPECT_NEAR(sum, volume, 1e-15) << physical;
  }
  const GmshMesh solid = read_gmsh(kMeshes / "cube_and_wedge.msh");
  const MeshBody<3> block(solid, "block", true), wedge(solid, "wedge", true);
  EXPECT_EQ(block.quadrature().size(), 8u);
  EXPECT_EQ(wedge.quadrature().size(), 4u);
  double vb = 0.0, vw = 0.0;
  for (const auto& q : block.quadrature()) vb += q.weight;
  for (const auto& q : wedge.quadrature()) {
    vw += q.weight;
    EXPECT_TRUE(wedge.contains(q.x));
  }
  EXPECT_NEAR(vb, 1.0, 1e-15);
  EXPECT_NEAR(vw, 1.0 / 6.0, 1e-15);

  // The slope example's gmsh mesh, its two groups as two bodies at their quadrature points.
  const fs::path example = fs::path(GRADMPM_SOURCE_DIR) / "examples" / "slope_gmsh_2d.toml";
  CaseFile cf = CaseFile::load(example, {"bodies[0].placement=elements", "bodies[1].placement=elements"});
  const Model<2> m = read_mpm_case<2>(cf).model;
  double v = 0.0, mass = 0.0;
  for (int p = 0; p < m.points.size(); ++p) {
    v += m.points.volume[p];
    mass += m.points.mass[p];
  }
  std::cout << "slope: " << m.points.size() << " points at the elements' quadrature points, volume " << v
            << " (the mesh's: 900), mass " << mass << "\n";
  EXPECT_NEAR(v, 900.0, 1e-12 * 900.0);
  EXPECT_NEAR(mass, 2.0 * v, 1e-12 * 900.0);
  EXPECT_THROW(
      {
        CaseFile bad = CaseFile::load(example, {"bodies[0].placement=elements", "bodies[0].points_per_cell=2"});
        read_mpm_case<2>(bad);
      },
      InputError);
}

namespace {
const char* kHoles = R"(
[grid]
origin = [0.0, 0.0]
cell_size = 0.5
cells = [8, 8]
[materials.soil]
model = "hencky"
young = 1.0e3
density = 1.0
[[bodies]]
material = "soil"
polygon = [[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0]]
holes = [[[1.0, 1.0], [3.0, 1.0], [3.0, 3.0], [1.0, 3.0]], [[0.5, 3.25], [1.5, 3.25], [1.5, 3.75], [0.5, 3.75]]]
points_per_cell = 4
[load_steps]
count = 1
)";
}  // namespace

TEST(Geometry, G5_PolygonsWithHoles) {
  CaseFile cf = CaseFile::parse(kHoles, "holes.toml");
  const Model<2> m = read_mpm_case<2>(cf).model;
  double v = 0.0;
  for (int p = 0; p < m.points.size(); ++p) {
    v += m.points.volume[p];
    const Vec<2>& x = m.points.position[p];
    EXPECT_FALSE(x[0] > 1.0 && x[0] < 3.0 && x[1] > 1.0 && x[1] < 3.0) << "a point in the first hole";
    EXPECT_FALSE(x[0] > 0.5 && x[0] < 1.5 && x[1] > 3.25 && x[1] < 3.75) << "a point in the second hole";
  }
  std::cout << "polygon with two holes: " << m.points.size() << " points, area " << v << " (16 - 4 - 0.5)\n";
  EXPECT_NEAR(v, 16.0 - 4.0 - 0.5, 1e-12);
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"bodies[0].holes=[[[1.0,1.0],[5.0,1.0],[3.0,3.0]]]", "bodies[0].holes[0]: expected a hole inside the body's polygon"},
      {"bodies[0].holes=[[[1.0,1.0],[3.0,1.0],[3.0,3.0]],[[2.5,1.5],[2.9,1.5],[2.9,2.0]]]",
       "expected a hole apart from bodies[0].holes[0]"},
      {"bodies[0].holes=[[[1.0,1.0],[3.0,1.0]]]", "bodies[0].holes[0]: expected at least 3 vertices"},
  };
  for (const auto& [set, message] : bad) {
    CaseFile b = CaseFile::parse(kHoles, "holes.toml", {set});
    try {
      read_mpm_case<2>(b);
      ADD_FAILURE() << set;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  }
}

namespace {
using Tri = std::array<Eigen::Vector3d, 3>;

/// The unit cube's 12 triangles, outward.
std::vector<Tri> unit_cube() {
  const auto v = [](int i) { return Eigen::Vector3d(i & 1, (i >> 1) & 1, (i >> 2) & 1); };
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  std::vector<Tri> out;
  for (const auto& f : faces) {
    out.push_back({v(f[0]), v(f[1]), v(f[2])});
    out.push_back({v(f[0]), v(f[2]), v(f[3])});
  }
  return out;
}

/// An octahedron of radius 1 about c, outward.
std::vector<Tri> octahedron(const Eigen::Vector3d& c) {
  std::vector<Tri> out;
  for (int sx : {-1, 1})
    for (int sy : {-1, 1})
      for (int sz : {-1, 1}) {
        Tri t = {c + Eigen::Vector3d(sx, 0, 0), c + Eigen::Vector3d(0, sy, 0), c + Eigen::Vector3d(0, 0, sz)};
        if (sx * sy * sz < 0) std::swap(t[1], t[2]);
        out.push_back(t);
      }
  return out;
}

void write_ascii_stl(const fs::path& file, const std::vector<Tri>& tris) {
  std::ofstream out(file);
  out << "solid test\n";
  for (const Tri& t : tris) {
    out << "  facet normal 0 0 0\n    outer loop\n";
    for (const auto& p : t) out << fmt::format("      vertex {} {} {}\n", p[0], p[1], p[2]);
    out << "    endloop\n  endfacet\n";
  }
  out << "endsolid test\n";
}

void write_binary_stl(const fs::path& file, const std::vector<Tri>& tris) {
  std::ofstream out(file, std::ios::binary);
  const std::string header(80, ' ');
  out.write(header.data(), 80);
  const std::uint32_t n = static_cast<std::uint32_t>(tris.size());
  out.write(reinterpret_cast<const char*>(&n), 4);
  for (const Tri& t : tris) {
    float v[12] = {0, 0, 0};
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) v[3 + 3 * k + d] = static_cast<float>(t[k][d]);
    out.write(reinterpret_cast<const char*>(v), 48);
    const std::uint16_t attribute = 0;
    out.write(reinterpret_cast<const char*>(&attribute), 2);
  }
}

std::string stl_case(const std::string& stl, double h, int cells, double origin) {
  return fmt::format(R"(
[grid]
origin = [{0}, {0}, {0}]
cell_size = {1}
cells = [{2}, {2}, {2}]
[materials.soil]
model = "hencky"
young = 1.0e3
density = 1.0
[[bodies]]
material = "soil"
stl = "{3}"
[load_steps]
count = 1
)",
                     origin, h, cells, stl);
}

class StlBodies : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/gradmpm-stl-XXXXXX";
    ASSERT_NE(::mkdtemp(tmpl), nullptr);
    dir = tmpl;
  }
  void TearDown() override { fs::remove_all(dir); }
  double points_volume(const std::string& text, int* count = nullptr) {
    CaseFile cf = CaseFile::parse(text, (dir / "case.toml").string());
    const Model<3> m = read_mpm_case<3>(cf).model;
    double v = 0.0;
    for (int p = 0; p < m.points.size(); ++p) v += m.points.volume[p];
    if (count) *count = m.points.size();
    return v;
  }
  fs::path dir;
};
}  // namespace

TEST_F(StlBodies, G6_ClosedSurfacesBoundTheirBodies) {
  write_ascii_stl(dir / "cube.stl", unit_cube());
  const StlBody cube(dir / "cube.stl");
  EXPECT_EQ(cube.triangles(), 12);
  EXPECT_NEAR(cube.volume(), 1.0, 1e-15);
  EXPECT_TRUE(cube.contains(Eigen::Vector3d(0.25, 0.25, 0.25)));  // on the x faces' diagonals' line
  EXPECT_TRUE(cube.contains(Eigen::Vector3d(0.5, 0.75, 0.75)));
  EXPECT_FALSE(cube.contains(Eigen::Vector3d(-0.25, 0.25, 0.25)));
  EXPECT_FALSE(cube.contains(Eigen::Vector3d(1.25, 0.5, 0.5)));
  int count = 0;
  const double v = points_volume(stl_case("cube.stl", 0.25, 8, -0.5), &count);
  std::cout << "unit cube (ASCII STL): " << count << " points, volume " << v << "\n";
  EXPECT_EQ(count, 512);
  EXPECT_NEAR(v, 1.0, 1e-12);

  // An octahedron (binary), off the grid's symmetry: the points' volume converges to 4/3.
  write_binary_stl(dir / "octahedron.stl", octahedron(Eigen::Vector3d(0.013, 0.021, 0.017)));
  EXPECT_NEAR(StlBody(dir / "octahedron.stl").volume(), 4.0 / 3.0, 1e-6);  // (float coordinates)
  double previous = 1.0;
  for (const int n : {10, 20, 40}) {
    const double h = 2.4 / n;
    const double error = std::abs(points_volume(stl_case("octahedron.stl", h, n, -1.2)) / (4.0 / 3.0) - 1.0);
    std::cout << "octahedron (binary STL), h = " << h << ": volume error " << error << "\n";
    EXPECT_LT(error, previous);
    previous = error;
  }
  EXPECT_LT(previous, 0.01);
}

TEST_F(StlBodies, G6_BadSurfacesAreRefusedNamingFileAndFault) {
  std::vector<Tri> open = unit_cube();
  open.pop_back();
  write_ascii_stl(dir / "open.stl", open);
  std::vector<Tri> flipped = unit_cube();
  std::swap(flipped[3][1], flipped[3][2]);
  write_ascii_stl(dir / "flipped.stl", flipped);
  write_ascii_stl(dir / "cube.stl", unit_cube());
  const std::vector<std::pair<std::string, std::string>> cases = {
      {stl_case("open.stl", 0.25, 8, -0.5), "open.stl: not a closed surface: the edge"},
      {stl_case("flipped.stl", 0.25, 8, -0.5), "flipped.stl: the triangles are not oriented alike"},
      {stl_case("missing.stl", 0.25, 8, -0.5), "missing.stl: cannot open the STL file"},
      {stl_case("cube.stl", 0.25, 8, -0.5) + "\n[[bodies]]\nmaterial = \"soil\"\nstl = \"cube.stl\"\nmin = [0, 0, 0]\n",
       "bodies[1].stl: expected either an STL surface, a mesh, a polygon or min/max"},
  };
  for (const auto& [text, message] : cases) {
    CaseFile cf = CaseFile::parse(text, (dir / "case.toml").string());
    try {
      read_mpm_case<3>(cf);
      ADD_FAILURE() << message;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  }
  CaseFile plane = CaseFile::parse(
      "[grid]\norigin = [0.0, 0.0]\ncell_size = 1.0\ncells = [4, 4]\n[materials.soil]\nmodel = \"hencky\"\nyoung = "
      "1.0e3\ndensity = 1.0\n[[bodies]]\nmaterial = \"soil\"\nstl = \"cube.stl\"\n[load_steps]\ncount = 1\n",
      (dir / "plane.toml").string());
  try {
    read_mpm_case<2>(plane);
    ADD_FAILURE() << "an STL surface in 2D";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bodies[0].stl: expected no STL surface in a 1D or 2D case"), std::string::npos)
        << e.what();
  }
}
