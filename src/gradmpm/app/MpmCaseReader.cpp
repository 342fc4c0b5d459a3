// Reads an MPM case file into one MpmCase value (app/MpmCase.hpp). Defaults, ranges
// and messages of every key come from app/CaseKeys.cpp; a material's keys from its law.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <memory>
#include <limits>

#include "gradmpm/app/CaseKeys.hpp"
#include "gradmpm/app/CommonKeys.hpp"
#include "gradmpm/app/MemoryCheck.hpp"
#include "gradmpm/app/MpmCase.hpp"
#include "gradmpm/core/Errors.hpp"
#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/geometry/GmshMesh.hpp"
#include "gradmpm/geometry/MeshBody.hpp"
#include "gradmpm/geometry/StlBody.hpp"
#include "gradmpm/materials/MaterialRegistry.hpp"
#include "gradmpm/mpm/InitialStress.hpp"
#include "gradmpm/mpm/RankPoints.hpp"
#include "gradmpm/mpm/RigidContact.hpp"
#include "gradmpm/points/Generate.hpp"

namespace gradmpm {

int mpm_case_dimension(const CaseFile& cf) {
  const auto n = cf.integer_list("grid.cells");
  cf.require(n.size() >= 1 && n.size() <= 3, "grid.cells", "1 to 3 cell counts (one per dimension)");
  return static_cast<int>(n.size());
}

namespace {

constexpr const char* kAxes[3] = {"x", "y", "z"};
/// The largest count numbered in an int (dofs, points): 2^31 - 1.
constexpr double kLargestIndex = std::numeric_limits<int>::max();

/// What the memory estimate needs besides the points and cells (app/MemoryCheck.hpp).
struct MemoryContext {
  int dim = 1;
  double nodes = 0.0;
  bool grid_output = false;
  double share = 1.0;       ///< of the points and the tangent on this rank: 1 / ranks
  int on_this_machine = 1;  ///< ranks sharing this machine's memory
  std::string machine_ranks;  ///< ", 2 of the 4 ranks on this machine" in messages
  double estimate(double points, double cells) const {
    return mpm_memory_estimate(dim, points, cells, nodes, grid_output, share, on_this_machine);
  }
};

MemoryContext memory_context(const CaseFile& cf, int dim, double nodes) {
  MemoryContext c;
  c.dim = dim;
  c.nodes = nodes;
  c.grid_output = read_integer(cf, "output", mpm_section("output").key("vtk_every")) > 0;
  // A distributed run's ranks on one machine: each its share of the points and the tangent.
  c.share = 1.0 / ranks::size();
  c.on_this_machine = ranks::on_this_machine();
  if (ranks::distributed())
    c.machine_ranks = fmt::format(", {} of the {} ranks on this machine", c.on_this_machine, ranks::size());
  return c;
}

template <int dim>
Vec<dim> vec(const CaseFile& cf, const std::string& key) {
  const auto v = cf.numbers(key, dim);
  Vec<dim> out;
  for (int d = 0; d < dim; ++d) out[d] = v[d];
  return out;
}

bool inside_polygon(const std::vector<std::vector<double>>& poly, double x, double y) {
  bool in = false;  // even-odd rule
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const double xi = poly[i][0], yi = poly[i][1], xj = poly[j][0], yj = poly[j][1];
    if ((yi > y) != (yj > y) && x < (xj - xi) * (y - yi) / (yj - yi) + xi) in = !in;
  }
  return in;
}

template <int dim>
struct Box {
  Vec<dim> lo, hi;
  bool contains(const Vec<dim>& x, double tol) const {
    for (int d = 0; d < dim; ++d)
      if (x[d] < lo[d] - tol || x[d] > hi[d] + tol) return false;
    return true;
  }
};

template <int dim>
Box<dim> read_box(const CaseFile& cf, const std::string& prefix) {
  Box<dim> b{vec<dim>(cf, prefix + ".min"), vec<dim>(cf, prefix + ".max")};
  for (int d = 0; d < dim; ++d)
    cf.require(b.hi[d] >= b.lo[d], prefix + ".max", fmt::format("a corner with max >= min in every direction"));
  return b;
}

/// A rigid box acts on points: one of no size, or whose path from load factor 0 to 1 never
/// meets the grid, could touch none; its name is its row in reactions.csv, so it is unique
/// among the named constraints and the boxes before it.
template <int dim>
void check_rigid_box(const CaseFile& cf, const std::string& k, const RigidBox<dim>& b, const Vec<dim>& origin,
                     const Vec<dim>& grid_hi, const Model<dim>& m) {
  const bool box = b.polygon.empty();
  bool meets = true;
  for (int d = 0; d < dim; ++d) {
    cf.require(b.hi[d] > b.lo[d], k + ".max", "a box of positive size in every direction");
    const double lo = std::min(b.lo[d], b.lo[d] + b.total[d]), hi = std::max(b.hi[d], b.hi[d] + b.total[d]);
    meets = meets && lo < grid_hi[d] && hi > origin[d];
  }
  cf.require(meets, k + (box ? ".min" : ".vertices"),
             fmt::format("a {} that meets the grid on its way (it could touch no material point)", box ? "box" : "body"));
  if (b.name.empty()) return;
  for (const auto& s : m.node_sets)
    cf.require(s.name != b.name, k + ".name", "a name no named constraint has (reactions.csv has one row per name)");
  for (const auto& other : m.rigid_boxes)
    cf.require(other.name != b.name, k + ".name", "a name no other rigid box or body has (reactions.csv has one row per name)");
}

/// [regularisation]: makes every softening material regularised (materials/PlasticLaw.hpp)
/// and keeps the settings of the nonlocal field in the model.
template <int dim>
void read_regularisation(const CaseFile& cf, const std::vector<std::string>& names, Model<dim>& m) {
  const SectionSpec& sec = regularisation_section();
  if (read_string(cf, sec.name, sec.key("type")) == "none") {
    for (const auto& key : sec.keys)
      if (key.name != "type")
        cf.require(!cf.has(sec.name + "." + key.name), sec.name + "." + key.name,
                   "no such key when regularisation.type = \"none\" (it would have no effect)");
    return;
  }
  m.regularisation.length_scale = read_number(cf, sec.name, sec.key("length_scale"));
  m.regularisation.start_from_points = read_string(cf, sec.name, sec.key("history")) == "points";
  m.regularisation.monolithic = read_string(cf, sec.name, sec.key("coupling")) == "monolithic";
  m.regularisation.max_iterations = static_cast<int>(read_integer(cf, sec.name, sec.key("max_iterations")));
  m.regularisation.tolerance = read_number(cf, sec.name, sec.key("tolerance"));
  const double weight = read_number(cf, sec.name, sec.key("nonlocal_weight"));
  int softening = 0;
  for (std::size_t i = 0; i < m.materials.size(); ++i) {
    if (!m.materials[i]->softens()) continue;
    auto regularised = m.materials[i]->regularised(weight);
    cf.require(
        regularised != nullptr, "materials." + names[i] + ".model",
        fmt::format("a law with an implicit-gradient regularisation (\"{}\" has none)", m.materials[i]->model()));
    m.materials[i] = std::move(regularised);
    ++softening;
  }
  cf.require(softening > 0, "regularisation.type",
             "\"none\" when no material softens (hardening < 0): implicit-gradient regularises softening laws only");
}

/// [grid]: the grid, checked to be numbered in 32-bit dofs and to fit in memory before
/// it exists. Also the sizes later checks need.
template <int dim>
struct GridRead {
  typename Grid<dim>::Index n;
  Vec<dim> origin, h, hi;  ///< the lower and upper corners, the cell sizes
  double nodes = 0.0;      ///< in 64 bits
  MemoryContext memory;
};

template <int dim>
GridRead<dim> read_grid(const CaseFile& cf) {
  GridRead<dim> g;
  const auto cells = cf.integer_list("grid.cells");
  for (int d = 0; d < dim; ++d) {
    cf.require(cells[d] >= 1 && cells[d] <= 10'000'000, "grid.cells", mpm_section("grid").key("cells").expected());
    g.n[d] = static_cast<int>(cells[d]);
  }
  g.origin = vec<dim>(cf, "grid.origin");
  if (cf.is_array("grid.cell_size"))  // one size for all directions, or one per direction
    g.h = vec<dim>(cf, "grid.cell_size");
  else
    g.h.setConstant(cf.number("grid.cell_size"));
  cf.require((g.h.array() > 0.0).all(), "grid.cell_size", mpm_section("grid").key("cell_size").expected());
  for (int d = 0; d < dim; ++d) g.hi[d] = g.origin[d] + g.n[d] * g.h[d];
  // Sizes in 64 bits before anything is allocated: the dofs are numbered in 32-bit ints.
  g.nodes = 1.0;
  for (int d = 0; d < dim; ++d) g.nodes *= static_cast<double>(cells[d]) + 1.0;
  cf.require(g.nodes * dim <= kLargestIndex, "grid.cells",
             fmt::format("a grid of at most {:.4g} nodes ({} dofs per node, numbered in 32 bits); this one has {:.4g}",
                         std::floor(kLargestIndex / dim), dim, g.nodes));
  g.memory = memory_context(cf, dim, g.nodes);
  require_memory(cf, "grid.cells", g.memory.estimate(0.0, 0.0),
                 fmt::format("{:.3g} grid nodes{}{}", g.nodes,
                             g.memory.grid_output ? " written to grid VTU files" : "", g.memory.machine_ranks));
  return g;
}

/// The pore fluid's keys of a [materials.NAME] section (read by read_pore_pressure).
constexpr const char* kPoreFluidKeys[] = {"permeability", "permeability_law", "porosity", "fluid_bulk_modulus",
                                          "fluid_density"};

/// [materials.NAME]: each law reads its own keys. Returns the names, in file order.
template <int dim>
std::vector<std::string> read_materials(const CaseFile& cf, Model<dim>& m) {
  const auto names = cf.subsections("materials");
  if (names.empty())
    throw InputError(fmt::format("{}: missing section [materials.NAME] (at least one material)", cf.name()));
  for (const auto& name : names) {
    // A dot or brackets would read as a key path (materials.so.il.model, bodies[0]), a
    // quote as the end of a name: refuse them by name.
    if (name.find_first_of(".[]\"") != std::string::npos || name.find_first_of("\n\r\t") != std::string::npos)
      throw InputError(
          fmt::format("{}: [materials.\"{}\"]: expected a material name without dots, brackets, quotes or line breaks",
                      cf.name(), name.find_first_of("\n\r\t") == std::string::npos ? name : std::string("...")));
    const std::string k = "materials." + name;
    const std::string model = read_string(cf, k, mpm_section("materials").key("model"));
    const MaterialInfo* law = MaterialRegistry::instance().find(model);
    cf.require(law != nullptr, k + ".model", mpm_section("materials").key("model").expected());
    std::vector<std::string> keys = {"model"};
    for (const auto& key : law->keys) keys.push_back(key.name);
    for (const char* key : kPoreFluidKeys) keys.push_back(key);
    cf.check_section_keys(k, keys, fmt::format("[{}] with model = \"{}\"", k, model));
    m.materials.push_back(law->make(cf, k, *law));
  }
  return names;
}

/// l^2 beside the cells' h^2 in the Helmholtz system: far beyond the grid's extent kappa_bar
/// is only the mean of kappa, and l = 1e300 overflowed l^2 into a solve of non-finite values.
template <int dim>
void check_length_scale(const CaseFile& cf, const Model<dim>& m, const GridRead<dim>& g) {
  double extent = 0.0;
  for (int d = 0; d < dim; ++d) extent = std::max(extent, g.n[d] * g.h[d]);
  cf.require(m.regularisation.length_scale <= 10.0 * extent, "regularisation.length_scale",
             fmt::format("a length scale l > 0 of at most 10 times the grid's extent ({:g})", 10.0 * extent));
}

/// A body's shape: its bounding box and whether a point lies inside (a box, or a 2D polygon).
template <int dim>
struct BodyShape {
  Box<dim> box;
  std::function<bool(const Vec<dim>&)> inside;
  std::string key;  ///< the key its errors name: "bodies[k].polygon" or "bodies[k].max"
  /// placement = "elements": the mesh whose quadrature points are the body's points
  std::shared_ptr<const MeshBody<dim>> elements;
};

/// A body from a mesh file (its path relative to the case file's folder): the elements of
/// its physical group `physical` (all of them where empty).
template <int dim>
std::shared_ptr<const MeshBody<dim>> read_mesh_body(const CaseFile& cf, const std::string& key,
                                                    const std::string& physical, bool quadrature) {
  std::filesystem::path file = cf.string(key);
  if (file.is_relative()) file = std::filesystem::path(cf.name()).parent_path() / file;
  try {
    return std::make_shared<const MeshBody<dim>>(read_gmsh(file), physical, quadrature);
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}: {}", cf.name(), key, e.what()));
  }
}

/// `holes` of a polygon body (k: "bodies[2]"): polygons of at least 3 vertices, each inside
/// the body's polygon and outside the other holes (every vertex).
std::vector<std::vector<std::vector<double>>> read_holes(const CaseFile& cf, const std::string& k,
                                                        const std::vector<std::vector<double>>& poly) {
  std::vector<std::vector<std::vector<double>>> holes;
  const std::string key = k + ".holes";
  if (!cf.has(key)) return holes;
  cf.require(cf.list_size(key) > 0, key, "an array of polygons [[[x, y], ...], ...]");
  for (std::size_t h = 0; h < cf.list_size(key); ++h) {
    const std::string hk = fmt::format("{}[{}]", key, h);
    holes.push_back(cf.vector_list(hk, 2));
    cf.require(holes.back().size() >= 3, hk, "at least 3 vertices");
    for (const auto& v : holes.back())
      cf.require(inside_polygon(poly, v[0], v[1]), hk,
                 fmt::format("a hole inside the body's polygon (its vertex ({:g}, {:g}) is not)", v[0], v[1]));
  }
  for (std::size_t a = 0; a < holes.size(); ++a)
    for (std::size_t b = 0; b < holes.size(); ++b)
      for (const auto& v : holes[a])
        cf.require(a == b || !inside_polygon(holes[b], v[0], v[1]), fmt::format("{}[{}]", key, a),
                   fmt::format("a hole apart from {}[{}] (its vertex ({:g}, {:g}) is inside it)", key, b, v[0], v[1]));
  return holes;
}

template <int dim>
BodyShape<dim> read_body_shape(const CaseFile& cf, const std::string& k, const GridRead<dim>& g) {
  BodyShape<dim> s;
  cf.require(!cf.has(k + ".holes") || cf.has(k + ".polygon"), k + ".holes",
             "no such key without a polygon (`polygon = [[x, y], ...]`)");
  for (const char* key : {".physical", ".placement"})
    cf.require(!cf.has(k + key) || cf.has(k + ".mesh"), k + key, "no such key without a mesh (`mesh = \"FILE.msh\"`)");
  const bool elements = cf.has(k + ".mesh") && read_string(cf, k, mpm_section("bodies").key("placement")) == "elements";
  if (elements) {
    cf.require(!cf.has(k + ".points_per_cell"), k + ".points_per_cell",
               "no such key with placement = \"elements\" (the points are the elements' quadrature points)");
    cf.require(!ranks::distributed(), k + ".placement", "\"grid\" in a run on more than one rank");
  }
  if (cf.has(k + ".stl")) {
    s.key = k + ".stl";
    cf.require(!cf.has(k + ".min") && !cf.has(k + ".max") && !cf.has(k + ".polygon") && !cf.has(k + ".mesh"), s.key,
               "either an STL surface, a mesh, a polygon or min/max, not two of them");
    cf.require(dim == 3, s.key, "no STL surface in a 1D or 2D case (an STL surface bounds a 3D body)");
    if constexpr (dim == 3) {
      std::filesystem::path file = cf.string(s.key);
      if (file.is_relative()) file = std::filesystem::path(cf.name()).parent_path() / file;
      std::shared_ptr<const StlBody> body;
      try {
        body = std::make_shared<const StlBody>(file);
      } catch (const InputError& e) {
        throw InputError(fmt::format("{}: {}: {}", cf.name(), s.key, e.what()));
      }
      s.box = {body->lo(), body->hi()};
      s.inside = [body](const Vec<dim>& x) { return body->contains(x); };
    }
  } else if (cf.has(k + ".mesh")) {
    s.key = k + ".mesh";
    cf.require(!cf.has(k + ".min") && !cf.has(k + ".max") && !cf.has(k + ".polygon"), s.key,
               "either a mesh, a polygon or min/max, not two of them");
    if constexpr (dim == 1) {
      cf.require(false, s.key, "no mesh in a 1D case (a mesh body is 2D or 3D)");
    } else {
      const auto body =
          read_mesh_body<dim>(cf, s.key, cf.has(k + ".physical") ? cf.string(k + ".physical") : "", elements);
      s.box = {body->lo(), body->hi()};
      s.inside = [body](const Vec<dim>& x) { return body->contains(x); };
      if (elements) s.elements = body;
    }
  } else if (cf.has(k + ".polygon")) {
    s.key = k + ".polygon";
    cf.require(dim == 2, s.key, "no polygon (polygons are for 2D cases; use min and max)");
    cf.require(!cf.has(k + ".min") && !cf.has(k + ".max"), s.key, "either a polygon or min/max, not both");
    const auto poly = cf.vector_list(s.key, 2);
    cf.require(poly.size() >= 3, s.key, "at least 3 vertices");
    s.box.lo.setConstant(std::numeric_limits<double>::max());
    s.box.hi.setConstant(std::numeric_limits<double>::lowest());
    for (const auto& v : poly)
      for (int d = 0; d < dim; ++d) {
        s.box.lo[d] = std::min(s.box.lo[d], v[d]);
        s.box.hi[d] = std::max(s.box.hi[d], v[d]);
      }
    const auto holes = read_holes(cf, k, poly);
    s.inside = [poly, holes](const Vec<dim>& x) {
      const double px = x[0], py = x[dim > 1 ? 1 : 0];
      if (!inside_polygon(poly, px, py)) return false;
      for (const auto& h : holes)
        if (inside_polygon(h, px, py)) return false;
      return true;
    };
  } else {
    s.key = k + ".max";
    s.box = read_box<dim>(cf, k);
    s.inside = [box = s.box](const Vec<dim>& x) { return box.contains(x, 0.0); };
  }
  for (int d = 0; d < dim; ++d)
    cf.require(s.box.lo[d] >= g.origin[d] - 1e-12 * g.h[d] && s.box.hi[d] <= g.hi[d] + 1e-12 * g.h[d], s.key,
               "a body inside the grid");
  return s;
}

/// What the bodies brought: the points planned (for the memory estimate) and made.
struct BodiesRead {
  double planned_points = 0.0, planned_cells = 0.0;
  long long total_points = 0;  ///< over every rank
};

/// A body's points to make once the ranks' cells are known (a distributed run).
template <int dim>
struct Fill {
  typename Grid<dim>::Index first, last;
  int ppc, material;
  std::function<bool(const Vec<dim>&)> inside;
  Vec<dim> velocity;
};

/// This rank's points (the cells of the cut), their ids in the order of every point.
template <int dim>
void make_rank_points(Model<dim>& m, const std::vector<Fill<dim>>& fills, const std::vector<long long>& per_key) {
  m.rank_boxes = RankBoxes::of_counts(cells_of(m.grid), per_key, ranks::size());
  const int me = ranks::rank();
  long long mine = 0;
  m.rank_boxes.for_each_cell(me, [&](int key) { mine += per_key[key]; });
  m.points.reserve(static_cast<std::size_t>(mine));
  m.point_ids.reserve(static_cast<std::size_t>(mine));
  int id = 0;
  for (const Fill<dim>& f : fills) {
    const int before = m.points.size();
    add_regular_points<dim>(m.grid, f.first, f.last, f.ppc, f.inside, f.material, m.materials[f.material]->density(),
                            m.points, [&](const Vec<dim>& x) {
                              const bool owned = m.rank_boxes.owner(cell_corner_key(m.grid, x)) == me;
                              if (owned) m.point_ids.push_back(id);
                              ++id;
                              return owned;
                            });
    for (int p = before; p < m.points.size(); ++p) m.points.velocity[p] = f.velocity;
  }
}

/// [[bodies]]: material points at sub-cell centres inside each body. A distributed run's
/// rank makes only the points in its cells (rank_points_only): the bodies are visited
/// twice, first to check and count their points per cell (nothing stored but the counts:
/// the cut of mpm/RankPoints.hpp), then to make this rank's.
template <int dim>
BodiesRead read_bodies(const CaseFile& cf, const std::vector<std::string>& names, const GridRead<dim>& g,
                       bool rank_points_only, Model<dim>& m) {
  const std::size_t nb = cf.array_size("bodies");
  if (nb == 0)
    throw InputError(fmt::format("{}: missing [[bodies]] (at least one body of material points)", cf.name()));
  BodiesRead r;
  std::vector<std::function<bool(const Vec<dim>&)>> earlier_bodies;  // their insides, strict
  std::vector<Fill<dim>> fills;
  std::vector<long long> per_key(rank_points_only ? m.grid.num_nodes() : 0, 0);
  for (std::size_t b = 0; b < nb; ++b) {
    const std::string k = fmt::format("bodies[{}]", b);
    const std::string mat = cf.string(k + ".material");
    const auto named = std::find(names.begin(), names.end(), mat);
    cf.require(named != names.end(), k + ".material",
               fmt::format("the name of a [materials.NAME] section (one of: {})", fmt::join(names, ", ")));
    const int mat_id = static_cast<int>(named - names.begin());
    const int ppc = static_cast<int>(read_integer(cf, k, mpm_section("bodies").key("points_per_cell")));
    const BodyShape<dim> shape = read_body_shape(cf, k, g);
    typename Grid<dim>::Index first, last;
    for (int d = 0; d < dim; ++d) {
      first[d] = std::max(0, static_cast<int>(std::floor((shape.box.lo[d] - g.origin[d]) / g.h[d])));
      last[d] = std::min(g.n[d], static_cast<int>(std::ceil((shape.box.hi[d] - g.origin[d]) / g.h[d])));
    }
    // The memory this body brings (with the bodies before it), before its points exist.
    double body_cells = 1.0;
    for (int d = 0; d < dim; ++d) body_cells *= std::max(0, last[d] - first[d]);
    r.planned_cells += body_cells;
    double body_points = body_cells * std::pow(static_cast<double>(ppc), dim);
    if constexpr (dim >= 2)
      if (shape.elements) body_points = static_cast<double>(shape.elements->quadrature().size());
    r.planned_points += body_points;
    require_memory(cf, shape.key, g.memory.estimate(r.planned_points, r.planned_cells),
                   fmt::format("{:.3g} points, {:.3g} grid nodes{}", r.planned_points, g.nodes, g.memory.machine_ranks));
    cf.require(r.planned_points <= kLargestIndex, k + ".points_per_cell",
               fmt::format("at most 2^31 points in all; these bodies have {:.4g}", r.planned_points));
    // Overlapping bodies would put two points' mass and stiffness in one place: refused.
    const bool box = !cf.has(k + ".polygon") && !cf.has(k + ".mesh");
    const std::string overlap_key = box ? k + ".min" : shape.key;
    auto not_overlapping = [&](const Vec<dim>& x) {
      for (std::size_t e = 0; e < earlier_bodies.size(); ++e)
        cf.require(!earlier_bodies[e](x), overlap_key,
                   fmt::format("a body that does not overlap bodies[{}] (its point at ({:.6g}) lies inside it: "
                               "mass and stiffness would count twice there)",
                               e, fmt::join(x.data(), x.data() + dim, ", ")));
    };
    const Vec<dim> velocity = cf.has(k + ".velocity") ? vec<dim>(cf, k + ".velocity") : Vec<dim>::Zero();
    cf.require(!cf.has(k + ".velocity") || cf.has_section("time"), k + ".velocity",
               "no initial velocity in a quasi-static case (a dynamic one has [time])");
    int added = 0;
    if (shape.elements) {  // the mesh's quadrature points (one rank: refused in a distributed run)
      if constexpr (dim >= 2)
        for (const auto& q : shape.elements->quadrature()) {
          not_overlapping(q.x);
          const double side = std::pow(q.weight, 1.0 / dim);  // (a GIMP domain of the point's volume)
          m.points.add(q.x, q.weight, mat_id, Vec<dim>::Constant(0.5 * side), m.materials[mat_id]->density() * q.weight);
          m.points.velocity[m.points.size() - 1] = velocity;
          ++added;
        }
    } else if (rank_points_only) {
      for_each_regular_point<dim>(m.grid, first, last, ppc, shape.inside, [&](const Vec<dim>& x) {
        not_overlapping(x);
        ++added;
        ++per_key[cell_corner_key(m.grid, x)];
      });
      fills.push_back({first, last, ppc, mat_id, shape.inside, velocity});
    } else {
      const int before = m.points.size();
      added = add_regular_points<dim>(m.grid, first, last, ppc, shape.inside, mat_id, m.materials[mat_id]->density(),
                                      m.points);
      for (int p = before; p < m.points.size(); ++p) {
        not_overlapping(m.points.position[p]);
        m.points.velocity[p] = velocity;
      }
    }
    r.total_points += added;
    if (!box)
      earlier_bodies.push_back(shape.inside);
    else
      earlier_bodies.push_back([box = shape.box, h = g.h](const Vec<dim>& x) {
        return box.contains(x, -1e-9 * h.minCoeff());
      });
    cf.require(added > 0, shape.key, "a body holding at least one material point (it is smaller than a sub-cell)");
  }
  if (rank_points_only) make_rank_points(m, fills, per_key);
  return r;
}

/// [mpm]: F-bar (finite-strain laws only) and the ghost penalty.
template <int dim>
void read_mpm_options(const CaseFile& cf, Model<dim>& m) {
  m.fbar = read_boolean(cf, "mpm", mpm_section("mpm").key("fbar"));
  for (const auto& mat : m.materials)
    cf.require(!m.fbar || mat->finite_strain(), "mpm.fbar",
               fmt::format("false with the small-strain model \"{}\" (F-bar needs finite-strain laws)", mat->model()));
  m.ghost_penalty = read_number(cf, "mpm", mpm_section("mpm").key("ghost_penalty"));
  m.axisymmetric = read_boolean(cf, "mpm", mpm_section("mpm").key("axisymmetric"));
  cf.require(!m.axisymmetric || dim == 2, "mpm.axisymmetric", "false in a 1D or 3D case (axisymmetry is 2D: r-z)");
}

/// [mpm] axisymmetric: what runs with it (the rest is refused, naming its key), and the
/// points' volumes and masses per radian: r_p times the area they were made with.
template <int dim>
void make_axisymmetric(const CaseFile& cf, const GradientSettings& gradient, const NewtonSettings& newton,
                       Model<dim>& m) {
  if (!m.axisymmetric) return;
  const std::string why = "with [mpm] axisymmetric = true (not built for r-z yet: docs/axisymmetry.md)";
  cf.require(m.ties.empty(), "ties", "no [[ties]] " + why);
  cf.require(!m.pore.active(), "pore_pressure", "no pore pressure " + why);
  cf.require(gradient.variant == GradientVariant::None, "gradient.variant", "\"none\" " + why);
  cf.require(!m.regularisation.monolithic, "regularisation.coupling", "\"staggered\" " + why);
  cf.require(!newton.arc_length.enabled, "arc_length", "no [arc_length] " + why);

  auto& pts = m.points;
  for (int p = 0; p < pts.size(); ++p) {
    const double r = pts.position[p][0];
    if (!(r > 0.0))
      throw InputError(fmt::format("{}: mpm.axisymmetric: expected every point at r = x > 0 (the axis is x = 0), "
                                   "got a point at x = {:g}",
                                   cf.name(), r));
    pts.volume[p] *= r;
    pts.original_volume[p] *= r;
    pts.mass[p] *= r;
  }
}

/// What every rigid body (block k of section `rigid`) reads and checks once its shape is
/// in b, and its joining the model: its travel, which must meet the grid; its penalty,
/// friction and adhesion; and no point's domain overlapping it at the start (no axis, the
/// grid's or a polygon's face normal, separating them by more than round-off).
template <int dim>
void add_rigid_body(const CaseFile& cf, const std::string& k, const SectionSpec& rigid, const GridRead<dim>& g,
                    RigidBox<dim> b, Model<dim>& m) {
  const bool box = b.polygon.empty();
  const double tol = 1e-9 * g.h.minCoeff();
  if (cf.has(k + ".displacement")) b.total = vec<dim>(cf, k + ".displacement");
  check_rigid_box(cf, k, b, g.origin, g.hi, m);
  b.stiffness = read_number(cf, k, rigid.key("penalty")) * stiffest_young(m.materials) / g.h.minCoeff();
  b.friction = read_number(cf, k, rigid.key("friction"));
  b.adhesion = read_number(cf, k, rigid.key("adhesion"));
  const auto faces = RigidContact<dim>::polygon_faces(b, 0.0);  // (none for a box)
  int overlapped = std::numeric_limits<int>::max();  // the first point (id) whose domain it overlaps
  for (int p = 0; p < m.points.size() && overlapped == std::numeric_limits<int>::max(); ++p) {
    const Vec<dim>&x = m.points.position[p], &l = m.points.half_length[p];
    bool inside = true;
    for (int d = 0; d < dim; ++d) inside = inside && x[d] + l[d] > b.lo[d] + tol && x[d] - l[d] < b.hi[d] - tol;
    for (const auto& f : faces) inside = inside && RigidContact<dim>::face_push(f, x, l) > tol;
    if (inside) overlapped = m.id_of(p);
  }
  overlapped = ranks::min(overlapped);  // (every rank's points)
  cf.require(overlapped == std::numeric_limits<int>::max(), k + (box ? ".min" : ".vertices"),
             fmt::format("a {} that no material point's domain overlaps at the start (point {} does)",
                         box ? "box" : "body", overlapped));
  m.rigid_boxes.push_back(b);
}

/// A convex polygon's vertices (key: "rigid_bodies[k].vertices"), anticlockwise: at least
/// 3, every corner turning the same way (collinear or repeated vertices refused).
template <int dim>
std::vector<Vec<dim>> read_convex_polygon(const CaseFile& cf, const std::string& key) {
  const auto list = cf.vector_list(key, 2);
  cf.require(list.size() >= 3, key, "at least 3 vertices [[x, y], ...]");
  std::vector<Vec<dim>> v;
  double scale = 0.0;
  for (const auto& p : list) {
    Vec<dim> x;
    for (int d = 0; d < dim; ++d) x[d] = p[d];
    v.push_back(x);
    scale = std::max(scale, x.cwiseAbs().maxCoeff());
  }
  const std::size_t n = v.size();
  auto turn = [&](std::size_t k) {  // the corner at vertex k: (v_k - v_k-1) x (v_k+1 - v_k)
    const Vec<dim> a = v[k] - v[(k + n - 1) % n], b = v[(k + 1) % n] - v[k];
    return a[0] * b[1] - a[1] * b[0];
  };
  double area = 0.0;
  for (std::size_t k = 0; k < n; ++k) area += v[k][0] * v[(k + 1) % n][1] - v[(k + 1) % n][0] * v[k][1];
  if (area < 0.0) std::reverse(v.begin(), v.end());
  for (std::size_t k = 0; k < n; ++k)
    cf.require(turn(k) > 1e-12 * scale * scale, key,
               fmt::format("a convex polygon, its vertices in order around it (vertex {} at ({:g}, {:g}) {})", k,
                           list[area < 0.0 ? n - 1 - k : k][0], list[area < 0.0 ? n - 1 - k : k][1],
                           std::abs(turn(k)) <= 1e-12 * scale * scale ? "is on a line with its neighbours"
                                                                      : "turns the other way"));
  return v;
}

/// [[rigid_bodies]] (mpm/RigidContact.hpp): convex polygons in 2D, kept with the rigid
/// boxes, after them (reactions.csv's rows follow that order); none may overlap a point's
/// domain at the start.
template <int dim>
void read_rigid_bodies(const CaseFile& cf, const GridRead<dim>& g, Model<dim>& m) {
  const SectionSpec& rigid = mpm_section("rigid_bodies");
  for (std::size_t c = 0; c < cf.array_size("rigid_bodies"); ++c) {
    const std::string k = fmt::format("rigid_bodies[{}]", c);
    cf.require(dim == 2, k + ".shape",
               "no [[rigid_bodies]] in a 1D or 3D case (their shapes are 2D and r-z; use [[rigid_boxes]])");
    read_string(cf, k, rigid.key("shape"));
    RigidBox<dim> b;
    if (cf.has(k + ".name")) b.name = read_string(cf, k, rigid.key("name"));
    cf.require(b.name.find_first_of(",\n\"") == std::string::npos, k + ".name",
               "a name without commas, quotes or newlines");
    b.polygon = read_convex_polygon<dim>(cf, k + ".vertices");
    b.lo = b.hi = b.polygon[0];
    for (const auto& v : b.polygon) {
      b.lo = b.lo.cwiseMin(v);
      b.hi = b.hi.cwiseMax(v);
    }
    add_rigid_body(cf, k, rigid, g, b, m);
  }
}

/// The nodes a [[constraints]] block selects: a face of the grid, or a box.
template <int dim>
Box<dim> constraint_selection(const CaseFile& cf, const std::string& k, const GridRead<dim>& g) {
  if (!cf.has(k + ".face")) return read_box<dim>(cf, k);
  const std::string face = cf.string(k + ".face");
  int axis = -1;
  for (int d = 0; d < dim; ++d)
    if (face.size() == 2 && face[0] == kAxes[d][0] && (face[1] == '-' || face[1] == '+')) axis = d;
  cf.require(axis >= 0, k + ".face",
             dim == 1 ? "\"x-\" or \"x+\""
                      : (dim == 2 ? "one of \"x-\", \"x+\", \"y-\", \"y+\""
                                  : "one of \"x-\", \"x+\", \"y-\", \"y+\", \"z-\", \"z+\""));
  cf.require(!cf.has(k + ".min") && !cf.has(k + ".max"), k + ".face", "either a face or min/max, not both");
  Box<dim> sel{g.origin, g.hi};
  if (face[1] == '-')
    sel.hi[axis] = g.origin[axis];
  else
    sel.lo[axis] = g.hi[axis];
  return sel;
}

/// The displacement components a block lists under `key` ("x", "y", "z"): those a
/// [[constraints]] block holds, or those a [[ties]] block ties.
template <int dim>
std::vector<int> listed_components(const CaseFile& cf, const std::string& k, const std::string& key,
                                   const std::string& what) {
  std::vector<int> comps;
  for (const auto& f : cf.string_list(k + "." + key)) {
    int axis = -1;
    for (int d = 0; d < dim; ++d)
      if (f == kAxes[d]) axis = d;
    cf.require(axis >= 0, k + "." + key,
               dim == 1 ? "[\"x\"]" : (dim == 2 ? "a list of \"x\", \"y\"" : "a list of \"x\", \"y\", \"z\""));
    comps.push_back(axis);
  }
  cf.require(!comps.empty(), k + "." + key, "at least one component to " + what);
  return comps;
}

/// The node set a named block reports its reaction under (reactions.csv); blocks of one
/// name form one set. nullptr for an unnamed block.
template <int dim>
NamedNodeSet* named_node_set(const CaseFile& cf, const std::string& k, Model<dim>& m) {
  if (!cf.has(k + ".name")) return nullptr;
  const std::string name = read_string(cf, k, mpm_section("constraints").key("name"));
  cf.require(!name.empty() && name.find_first_of(",\n\"") == std::string::npos, k + ".name",
             "a name without commas, quotes or newlines");
  for (auto& s : m.node_sets)
    if (s.name == name) return &s;
  return &m.node_sets.emplace_back(NamedNodeSet{name, {}});
}

/// [[constraints]] on grid nodes.
template <int dim>
void read_constraints(const CaseFile& cf, const GridRead<dim>& g, Model<dim>& m) {
  const double tol = 1e-9 * g.h.minCoeff();
  for (std::size_t c = 0; c < cf.array_size("constraints"); ++c) {
    const std::string k = fmt::format("constraints[{}]", c);
    const Box<dim> sel = constraint_selection(cf, k, g);
    const std::vector<int> comps = listed_components<dim>(cf, k, "fix", "hold");
    const bool roller = static_cast<int>(comps.size()) < dim;
    Vec<dim> disp = Vec<dim>::Zero();
    if (cf.has(k + ".displacement")) disp = vec<dim>(cf, k + ".displacement");
    NamedNodeSet* named = named_node_set(cf, k, m);
    const bool boundary = read_boolean(cf, k, mpm_section("constraints").key("gradient_boundary"));
    if (roller && boundary)
      for (int d : comps)
        if (sel.hi[d] - sel.lo[d] <= tol) m.roller_planes.push_back({d, sel.lo[d]});
    int selected = 0;
    for (int node = 0; node < m.grid.num_nodes(); ++node) {
      if (!sel.contains(m.grid.node_position(node), tol)) continue;
      ++selected;
      for (int comp : comps) m.constraints.push_back({node, comp, disp[comp], roller, boundary});
      if (named && std::find(named->nodes.begin(), named->nodes.end(), node) == named->nodes.end())
        named->nodes.push_back(node);
    }
    cf.require(selected > 0, k + (cf.has(k + ".face") ? ".face" : ".min"), "a node set holding at least one grid node");
  }
}

/// [[ties]]: every node of the set tied to its neighbour along each grid direction in the
/// set, in each component listed.
template <int dim>
void read_ties(const CaseFile& cf, const GridRead<dim>& g, Model<dim>& m) {
  const double tol = 1e-9 * g.h.minCoeff();
  for (std::size_t c = 0; c < cf.array_size("ties"); ++c) {
    const std::string k = fmt::format("ties[{}]", c);
    cf.require(!ranks::distributed(), k, "a run on one rank ([[ties]] are serial)");
    const Box<dim> sel = constraint_selection(cf, k, g);
    const std::vector<int> comps = listed_components<dim>(cf, k, "components", "tie");
    const double stiffness = read_number(cf, k, mpm_section("ties").key("penalty")) * stiffest_young(m.materials) *
                             std::pow(g.h.minCoeff(), dim - 2);
    int pairs = 0;
    for (int node = 0; node < m.grid.num_nodes(); ++node) {
      if (!sel.contains(m.grid.node_position(node), tol)) continue;
      const auto ijk = m.grid.node_ijk(node);
      for (int d = 0; d < dim; ++d) {
        auto next = ijk;
        if (++next[d] > g.n[d]) continue;
        const int other = m.grid.node_index(next);
        if (!sel.contains(m.grid.node_position(other), tol)) continue;
        for (int comp : comps) m.ties.push_back({node, other, comp, stiffness});
        ++pairs;
      }
    }
    cf.require(pairs > 0, k + (cf.has(k + ".face") ? ".face" : ".min"), "a node set holding at least two neighbouring grid nodes");
  }
}

/// [[rigid_boxes]] (mpm/RigidContact.hpp): none may overlap a point's domain at the start.
template <int dim>
void read_rigid_boxes(const CaseFile& cf, const GridRead<dim>& g, Model<dim>& m) {
  const SectionSpec& rigid = mpm_section("rigid_boxes");
  for (std::size_t c = 0; c < cf.array_size("rigid_boxes"); ++c) {
    const std::string k = fmt::format("rigid_boxes[{}]", c);
    const Box<dim> box = read_box<dim>(cf, k);
    RigidBox<dim> b{cf.has(k + ".name") ? read_string(cf, k, rigid.key("name")) : "", box.lo, box.hi};
    cf.require(b.name.find_first_of(",\n\"") == std::string::npos, k + ".name",
               "a name without commas, quotes or newlines");
    add_rigid_body(cf, k, rigid, g, b, m);
  }
}

/// [[point_loads]]: a force on every point in a box (at least one, over every rank).
template <int dim>
void read_point_loads(const CaseFile& cf, const GridRead<dim>& g, Model<dim>& m) {
  const double tol = 1e-9 * g.h.minCoeff();
  for (std::size_t c = 0; c < cf.array_size("point_loads"); ++c) {
    const std::string k = fmt::format("point_loads[{}]", c);
    const Box<dim> sel = read_box<dim>(cf, k);
    const Vec<dim> f = vec<dim>(cf, k + ".force");
    double selected = 0;
    for (int p = 0; p < m.points.size(); ++p)
      if (sel.contains(m.points.position[p], tol)) {
        m.points.force[p] += f;
        ++selected;
      }
    ranks::sum(&selected, 1);  // (every rank's points)
    cf.require(selected > 0, k + ".min", "a box holding at least one material point");
  }
}

/// [time]: a dynamic analysis (none: TimeSettings::dt = 0, quasi-static). Prescribed
/// displacements need a ramp: without one the loads act in full from t = 0, and a
/// displacement that jumped to its total in the first step would be no physics.
template <int dim>
void read_time(const CaseFile& cf, Model<dim>& m) {
  if (!cf.has_section("time")) return;
  const SectionSpec& t = mpm_section("time");
  cf.require(!cf.has_section("load_steps"), "load_steps",
             "no [load_steps] in a dynamic case ([time] sets the steps: dt, end_time)");
  cf.require(!cf.has_section("arc_length"), "arc_length", "no [arc_length] in a dynamic case ([time])");
  TimeSettings& time = m.time;
  time.dt = read_number(cf, t.name, t.key("dt"));
  time.end_time = read_number(cf, t.name, t.key("end_time"));
  cf.require(time.dt <= time.end_time, "time.dt", fmt::format("a time step no longer than end_time = {:g}", time.end_time));
  time.scheme = read_string(cf, t.name, t.key("scheme")) == "newmark" ? TimeSettings::Scheme::Newmark
                                                                      : TimeSettings::Scheme::GeneralisedAlpha;
  time.beta = read_number(cf, t.name, t.key("beta"));
  time.gamma = read_number(cf, t.name, t.key("gamma"));
  time.rho_inf = read_number(cf, t.name, t.key("rho_inf"));
  time.ramp_time = read_number(cf, t.name, t.key("ramp_time"));
  time.consistent_mass = read_string(cf, t.name, t.key("mass")) == "consistent";
  time.damping = read_number(cf, t.name, t.key("damping"));
  time.stop_at_rest = read_number(cf, t.name, t.key("stop_at_rest"));
  time.pic_fraction = read_number(cf, t.name, t.key("pic_fraction"));
  time.inertia = read_boolean(cf, t.name, t.key("inertia"));
  if (time.ramp_time > 0.0) return;
  for (const auto& c : m.constraints)
    cf.require(c.total == 0.0, "time.ramp_time",
               "a ramp time > 0 where a displacement other than 0 is prescribed ([[constraints]])");
  for (const auto& b : m.rigid_boxes)
    cf.require(b.total.isZero(), "time.ramp_time", "a ramp time > 0 where a rigid body moves ([[rigid_boxes]], [[rigid_bodies]])");
}

/// [initial_stress]: every point starts from the geostatic stress (mpm/InitialStress.hpp).
template <int dim>
void read_initial_stress(const CaseFile& cf, const std::vector<std::string>& names, Model<dim>& m) {
  if (!cf.has_section("initial_stress")) {
    // (Modified Cam-Clay's ratio sets P_c from the initial stress; without one it would be ignored)
    for (const std::string& name : names) {
      const std::string key = "materials." + name + ".overconsolidation_ratio";
      cf.require(!cf.has(key), key, "no such key without [initial_stress] (P_c starts at pc0 then)");
    }
    return;
  }
  const SectionSpec& sec = mpm_section("initial_stress");
  cf.require(!ranks::distributed(), "initial_stress", "a run on one rank (the overburden is summed over columns of points)");
  cf.require(vertical_axis<dim>(m.gravity) >= 0, "loads.gravity", "gravity along one grid axis ([initial_stress] needs it)");
  InitialStressSettings s;
  cf.require(cf.has("initial_stress.k0"), "initial_stress.k0", sec.key("k0").expected());
  s.k0 = read_number(cf, sec.name, sec.key("k0"));
  if (m.pore.active())
    cf.require(m.pore.water_table.has_value(), "pore_pressure.water_table",
               "the water table's elevation ([initial_stress] with pore pressure starts p from it)");
  const GeostaticProblem problem = start_geostatic(m, s);
  cf.require(problem.empty(), problem.key, problem.expected);
}

/// [pore_pressure], the materials' fluid keys and [[pressure_constraints]]
/// (mpm/PorePressure.hpp). Where the case has no pore pressure, none of them may be given:
/// a permeability without [pore_pressure] would be ignored without a word.
template <int dim>
void read_pore_pressure(const CaseFile& cf, const std::vector<std::string>& names, const GridRead<dim>& g,
                        const NewtonSettings& newton, Model<dim>& m) {
  const SectionSpec& sec = mpm_section("pore_pressure");
  PoreSettings& pore = m.pore;
  if (cf.has_section("pore_pressure")) {
    const std::string drainage = read_string(cf, sec.name, sec.key("drainage"));
    pore.drainage = drainage == "coupled"     ? PoreSettings::Drainage::Coupled
                    : drainage == "undrained" ? PoreSettings::Drainage::Undrained
                                              : PoreSettings::Drainage::Drained;
    pore.stabilisation = read_number(cf, sec.name, sec.key("stabilisation"));
  }
  const SectionSpec& mat = mpm_section("materials");
  for (const auto& name : names) {
    const std::string k = "materials." + name;
    for (const char* key : kPoreFluidKeys)
      cf.require(pore.active() || !cf.has(k + "." + key), k + "." + key,
                 "no pore-fluid key without pore pressure ([pore_pressure] drainage = \"undrained\" or \"coupled\")");
    PoreFluid f;
    if (pore.active()) {
      cf.require(cf.has(k + ".porosity"), k + ".porosity", "a porosity in (0, 1) (the case has pore pressure)");
      f.porosity = read_number(cf, k, mat.key("porosity"));
      f.bulk_modulus = read_number(cf, k, mat.key("fluid_bulk_modulus"));
      f.density = read_number(cf, k, mat.key("fluid_density"));
    }
    if (pore.flows()) {
      cf.require(cf.has(k + ".permeability"), k + ".permeability",
                 "a hydraulic conductivity k >= 0 (m/s; [pore_pressure] drainage = \"coupled\")");
      f.conductivity = read_number(cf, k, mat.key("permeability"));
      f.kozeny_carman = read_string(cf, k, mat.key("permeability_law")) == "kozeny-carman";
    } else {
      for (const char* key : {"permeability", "permeability_law"})
        cf.require(!cf.has(k + "." + key), k + "." + key,
                   fmt::format("no {} unless [pore_pressure] drainage = \"coupled\" (undrained: no flow)", key));
    }
    pore.fluids.push_back(f);
  }
  if (m.gravity.norm() > 0.0) pore.gravity = m.gravity.norm();
  if (cf.has("pore_pressure.water_table")) {
    cf.require(pore.active(), "pore_pressure.water_table",
               "no water table without pore pressure ([pore_pressure] drainage = \"undrained\" or \"coupled\")");
    cf.require(vertical_axis<dim>(m.gravity) >= 0, "loads.gravity",
               "gravity along one grid axis ([pore_pressure] water_table needs it)");
    pore.water_table = read_number(cf, "pore_pressure", mpm_section("pore_pressure").key("water_table"));
  }
  const double tol = 1e-9 * g.h.minCoeff();
  for (std::size_t c = 0; c < cf.array_size("pressure_constraints"); ++c) {
    const std::string k = fmt::format("pressure_constraints[{}]", c);
    cf.require(pore.active(), k, "[[pressure_constraints]] only with pore pressure ([pore_pressure] drainage = \"undrained\" or \"coupled\")");
    const Box<dim> sel = constraint_selection(cf, k, g);
    const double value = read_number(cf, k, mpm_section("pressure_constraints").key("pressure"));
    int selected = 0;
    for (int node = 0; node < m.grid.num_nodes(); ++node)
      if (sel.contains(m.grid.node_position(node), tol)) {
        pore.constraints.push_back({node, value, static_cast<int>(c)});
        ++selected;
      }
    cf.require(selected > 0, k + (cf.has(k + ".face") ? ".face" : ".min"), "a node set holding at least one grid node");
  }
  if (!pore.active()) return;
  cf.require(!newton.arc_length.enabled, "arc_length", "no arc-length control with pore pressure");
  cf.require(!ranks::distributed(), "pore_pressure", "a run on one rank (the u-p step is serial)");
  if (pore.flows())
    cf.require(m.time.dynamic() && !m.time.inertia, "time",
               "a [time] section with inertia = false: consolidation advances in time (dt, end_time); dynamic u-p "
               "is not built");
  else
    cf.require(!m.time.inertial(), "time.inertia", "inertia = false with pore pressure (dynamic u-p is not built)");
}

/// [[point_sets]]: the points in each box (at least one), for the consolidation reports.
template <int dim>
void read_point_sets(const CaseFile& cf, const GridRead<dim>& g, Model<dim>& m) {
  const double tol = 1e-9 * g.h.minCoeff();
  const SectionSpec& spec = mpm_section("point_sets");
  for (std::size_t c = 0; c < cf.array_size("point_sets"); ++c) {
    const std::string k = fmt::format("point_sets[{}]", c);
    cf.require(m.pore.active(), k,
               "a case with pore pressure ([pore_pressure] drainage = \"undrained\" or \"coupled\"): a point set "
               "reports its degree of consolidation");
    PointSet set{read_string(cf, k, spec.key("name")), {}};
    cf.require(!set.name.empty() && set.name.find_first_of(",\n\"") == std::string::npos, k + ".name",
               "a name without commas, quotes or newlines");
    for (const PointSet& other : m.point_sets)
      cf.require(other.name != set.name, k + ".name", "a name no other point set has");
    const Box<dim> box = read_box<dim>(cf, k);
    for (int p = 0; p < m.points.size(); ++p)
      if (box.contains(m.points.position[p], tol)) set.points.push_back(p);
    cf.require(!set.points.empty(), k + ".min", "a box that holds at least one material point");
    m.point_sets.push_back(std::move(set));
  }
}

/// regularisation.coupling = "monolithic" solves quasi-static load steps on one rank.
template <int dim>
void check_monolithic_coupling(const CaseFile& cf, const NewtonSettings& newton, const Model<dim>& m) {
  if (!m.regularisation.monolithic) return;
  const std::string key = "regularisation.coupling";
  cf.require(!ranks::distributed(), key, "\"staggered\" in a run on more than one rank (the monolithic step is serial)");
  cf.require(!newton.arc_length.enabled, key, "\"staggered\" with [arc_length]");
  cf.require(!m.time.dynamic(), key, "\"staggered\" with [time] (the monolithic step is a quasi-static load step's)");
  cf.require(!m.pore.active(), key, "\"staggered\" with pore pressure");
}

/// [arc_length] method = "relative-displacement": the grid nodes nearest `from` and `to`.
template <int dim>
void read_arc_nodes(const CaseFile& cf, const GridRead<dim>& g, ArcLengthSettings& arc) {
  const SectionSpec& a = mpm_section("arc_length");
  const std::string method = read_string(cf, a.name, a.key("method"));
  for (const char* key : {"from", "to", "at"}) {
    const bool used = method == "displacement" ? key[0] == 'a' : method == "relative-displacement" && key[0] != 'a';
    cf.require(used || !cf.has(std::string("arc_length.") + key), std::string("arc_length.") + key,
               fmt::format("no such key with method = \"{}\"", method));
  }
  if (method == "cylindrical") return;
  const bool single = method == "displacement";
  arc.method = single ? ArcLengthSettings::Method::Displacement : ArcLengthSettings::Method::RelativeDisplacement;
  const std::string axis = read_string(cf, a.name, a.key("component"));
  arc.component = axis == "x" ? 0 : axis == "y" ? 1 : 2;
  cf.require(arc.component < dim, "arc_length.component", fmt::format("a component of a {}D case", dim));
  for (const char* key : single ? std::vector<const char*>{"at"} : std::vector<const char*>{"from", "to"}) {
    const std::string name = std::string("arc_length.") + key;
    cf.require(cf.has(name), name,
               single ? "a point (displacement control needs `at`)"
                      : "a point (relative-displacement control needs `from` and `to`)");
    const Vec<dim> x = vec<dim>(cf, name);
    typename Grid<dim>::Index ijk{};
    for (int d = 0; d < dim; ++d) {
      ijk[d] = static_cast<int>(std::lround((x[d] - g.origin[d]) / g.h[d]));
      cf.require(ijk[d] >= 0 && ijk[d] <= g.n[d], name, "a point inside the grid");
    }
    (key[0] == 'f' ? arc.from_node : arc.to_node) = Grid<dim>(g.origin, g.h, g.n).node_index(ijk);
  }
  if (!single) cf.require(arc.from_node != arc.to_node, "arc_length.to", "a grid node other than from's");
}

/// [load_steps] and [nonlinear_solver].
NewtonSettings read_newton(const CaseFile& cf) {
  const SectionSpec& nl = mpm_section("nonlinear_solver");
  NewtonSettings newton;
  if (cf.has_section("arc_length")) {
    const SectionSpec& a = mpm_section("arc_length");
    cf.require(!cf.has_section("load_steps") && !cf.has_section("time"), "arc_length",
               "arc-length control alone: no [load_steps] or [time] with it");
    ArcLengthSettings& arc = newton.arc_length;
    arc.enabled = true;
    arc.max_steps = static_cast<int>(read_integer(cf, a.name, a.key("max_steps")));
    arc.initial_increment = read_number(cf, a.name, a.key("initial_increment"));
    arc.max_load_factor = read_number(cf, a.name, a.key("max_load_factor"));
    arc.target_iterations = static_cast<int>(read_integer(cf, a.name, a.key("target_iterations")));
    cf.require(arc.initial_increment <= arc.max_load_factor, "arc_length.initial_increment",
               "a first load factor no larger than max_load_factor");
  } else if (!cf.has_section("time")) {
    cf.require(cf.has_section("load_steps"), "load_steps.count",
               "a number of load steps ([load_steps] count), a [time] section for a dynamic analysis, or "
               "[arc_length]");
    newton.load_steps = static_cast<int>(read_integer(cf, "load_steps", mpm_section("load_steps").key("count")));
  }
  newton.tolerance = read_number(cf, nl.name, nl.key("tolerance"));
  newton.max_iterations = static_cast<int>(read_integer(cf, nl.name, nl.key("max_iterations")));
  newton.max_cuts = static_cast<int>(read_integer(cf, nl.name, nl.key("max_cuts")));
  newton.linear_solver = read_linear_solver_settings(cf);
  return newton;
}

/// [output]; check = "column" only where the column's closed form holds.
template <int dim>
MpmOutputSettings read_output(const CaseFile& cf, const Model<dim>& m, long long total_points) {
  const SectionSpec& out = mpm_section("output");
  MpmOutputSettings output;
  output.vtk_every = static_cast<int>(read_integer(cf, out.name, out.key("vtk_every")));
  if (cf.has("output.track")) {
    output.track = cf.integer_list("output.track");
    for (long long id : output.track)
      cf.require(id >= 0 && id < total_points, "output.track", fmt::format("point ids from 0 to {}", total_points - 1));
  }
  output.check = read_string(cf, out.name, out.key("check"));
  output.plot = read_boolean(cf, out.name, out.key("plot"));
  output.checkpoint_every = static_cast<int>(read_integer(cf, out.name, out.key("checkpoint_every")));
  output.checkpoint_keep = static_cast<int>(read_integer(cf, out.name, out.key("checkpoint_keep")));
  if (output.check == "column") {
    cf.require(
        m.materials.size() == 1 && m.materials[0]->model() == "hencky" && m.materials[0]->elasticity().poisson == 0.0,
        "output.check", "\"column\" only for one Hencky material with poisson = 0");
    cf.require(cf.array_size("bodies") == 1 && !cf.has("bodies[0].polygon"), "output.check",
               "\"column\" only for one box-shaped body");
    bool vertical = m.gravity[dim - 1] < 0.0;
    for (int d = 0; d + 1 < dim; ++d) vertical = vertical && m.gravity[d] == 0.0;
    cf.require(vertical, "output.check", "\"column\" only with gravity along -" + std::string(kAxes[dim - 1]));
  }
  return output;
}

}  // namespace

template <int dim>
MpmCase<dim> read_mpm_case(CaseFile& cf, bool rank_points_only) {
  for (const auto& s : mpm_sections())
    if (s.name == "linear_solver")
      declare_linear_solver_section(cf);
    else
      cf.declare(s);
  cf.reject_unknown();
  const GradientSettings gradient_settings = read_gradient_settings(cf);
  const GridRead<dim> g = read_grid<dim>(cf);
  Model<dim> m(Grid<dim>(g.origin, g.h, g.n));
  m.basis = *parse_basis(read_string(cf, "basis", mpm_section("basis").key("type")));
  const std::vector<std::string> names = read_materials(cf, m);
  read_regularisation(cf, names, m);
  check_length_scale(cf, m, g);
  const BodiesRead bodies = read_bodies(cf, names, g, rank_points_only, m);
  read_mpm_options(cf, m);
  if (cf.has("loads.gravity")) m.gravity = vec<dim>(cf, "loads.gravity");
  read_constraints(cf, g, m);
  read_rigid_boxes(cf, g, m);
  read_rigid_bodies(cf, g, m);
  read_ties(cf, g, m);
  read_point_loads(cf, g, m);
  read_time(cf, m);
  NewtonSettings newton = read_newton(cf);
  if (newton.arc_length.enabled) read_arc_nodes(cf, g, newton.arc_length);
  if (newton.arc_length.enabled)  // the boxes are placed for a step's end, which arc-length finds
    cf.require(m.rigid_boxes.empty(), "arc_length",
               "no [[rigid_boxes]] or [[rigid_bodies]] with arc-length control (they move with load steps only)");
  read_pore_pressure(cf, names, g, newton, m);
  check_monolithic_coupling(cf, newton, m);
  const std::string line_search = read_string(cf, "nonlinear_solver", mpm_section("nonlinear_solver").key("line_search"));
  newton.line_search = line_search == "on";
  for (const auto& b : m.rigid_boxes)  // (auto: frictional contact's partial slip needs it)
    newton.line_search = newton.line_search || (line_search == "auto" && (b.friction > 0.0 || b.adhesion > 0.0));
  read_point_sets(cf, g, m);
  GradientSettings gradient = gradient_settings;
  gradient.linear_solver = newton.linear_solver;
  const MpmOutputSettings output = read_output(cf, m, bodies.total_points);
  make_axisymmetric(cf, gradient, newton, m);
  m.initialise_state();
  read_initial_stress(cf, names, m);  // (writes the states)
  // (one process's share of the machine's estimate, which a run prints beside its peak)
  const double memory = g.memory.estimate(bodies.planned_points, bodies.planned_cells) / g.memory.on_this_machine;
  return MpmCase<dim>{std::move(m), newton, gradient, output, memory};
}

template MpmCase<1> read_mpm_case<1>(CaseFile&, bool);
template MpmCase<2> read_mpm_case<2>(CaseFile&, bool);
template MpmCase<3> read_mpm_case<3>(CaseFile&, bool);

}  // namespace gradmpm
