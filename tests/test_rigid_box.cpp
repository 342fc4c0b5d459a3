// Requirements on rigid boxes (mpm/RigidContact.hpp, [[rigid_boxes]]):
//  R1 a column resting on a rigid box (no grid constraint below it) is carried by the box:
//     its contact force equals the weight at every step (1e-8), the column's top settles
//     by the closed form of the Hencky column plus the penetration q / k, to within what
//     the bottom point's (uGIMP, fixed-size) domain does not follow of the compression, and
//     Newton converges quadratically with the contact;
//  R2 the tangent with active contacts is the derivative of the internal force (central
//     differences, 1e-6 relative);
//  R3 a box that overlaps the points at the start is refused, naming the key;
//  R4 with Coulomb friction (sticking and sliding contacts of a box pressed into a plastic
//     block and moved sideways), the tangent is the derivative of the internal force
//     (1e-6 relative);
//  R5 a block dragged on a rough plane (a rigid box moving under it, the block's top held
//     sideways, gravity pressing it down), nu = 0 and 0.3: sliding, the plane's shear on
//     it is mu times its pressure to 1e-8 at every step; a drag too small to overcome the
//     friction sticks (shear below half of mu N; with nu = 0.3 in partial slip, the edges
//     slipping outward), and the stick carries over from step to step; the partial slip
//     converges with the line search (on by default with friction) and not without it;
//  R6 a rigid polygon ([[rigid_bodies]] shape = "polygon") that is a box gives the box's
//     answers, smooth and rough (contact forces at every step, 1e-12 relative);
//  R7 a rough polygon (a wedge pressed into the plastic block and moved sideways, its
//     contacts on inclined faces and on its bounding box's), the tangent is the derivative
//     of the internal force (1e-6 relative);
//  R8 a frictionless polygon pushes along its face's normal: a ramp (bottom face of slope
//     0.1) pressed into the block gives a force with F_x / F_y = -0.1 (1e-10);
//  R9 bad polygons are refused, naming the key: fewer than 3 vertices, not convex, in 3D,
//     overlapping a point at the start.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <iostream>
#include <vector>

#include <fmt/format.h>

#include "MpmTestUtil.hpp"
#include "PlasticityTestUtil.hpp"
#include "gradmpm/app/MpmCase.hpp"
#include "gradmpm/mpm/LoadStep.hpp"

using namespace gradmpm;

namespace {
// The large-deformation column of test_mpm_column (H0 = 10, E = 80, rho g = 10) in 1D on a
// rigid box y <= 0 instead of fixed nodes.
const char* kColumn = R"(
[grid]
origin = [-2.0]
cell_size = 0.5
cells = [26]
[basis]
type = "gimp"
[materials.a]
model = "hencky"
young = 80.0
density = 1.0
[[bodies]]
material = "a"
min = [0.0]
max = [10.0]
[loads]
gravity = [-10.0]
[[rigid_boxes]]
name = "base"
min = [-5.0]
max = [0.0]
penalty = 1000.0
[load_steps]
count = 10
[output]
vtk_every = 0
)";
}  // namespace

TEST(RigidBox, CarriesAColumnRestingOnIt) {
  CaseFile cf = CaseFile::parse(kColumn, "column.toml");
  MpmCase<1> c = read_mpm_case<1>(cf);
  ASSERT_EQ(c.model.rigid_boxes.size(), 1u);
  const double weight = 10.0 * 10.0;  // rho0 g H0 per unit area
  double worst = 0.0;
  test::QuadraticRate rate;
  run_quasi_static<1>(c.model, c.newton, [&](const Model<1>&, const StepInfo& info) {
    const Vector F = info.rigid_forces();
    worst = std::max(worst, std::abs(F[0] - info.load_factor * weight) / weight);
    rate.add(info.residuals);
  });
  std::cout << "rigid base: |F - weight| / weight <= " << worst << ", worst log-ratio " << rate.worst << " over "
            << rate.checked << " iterations\n";
  EXPECT_LT(worst, 1e-8);
  EXPECT_GE(rate.worst, 1.8);
  EXPECT_GT(rate.checked, 3);
  // The top: the closed form (fixed base) lowered by the penetration of the bottom point,
  // g = weight / (k A), k = 1000 E / h, and raised by at most what the bottom point's uGIMP
  // domain does not shrink: the box holds the domain (half-length l_p = h/4 = 0.125), not
  // the material, which is compressed to the stretch exp(-rho g H0 / E) at the base.
  double top = 0.0, top0 = 0.0;
  for (int p = 0; p < c.model.points.size(); ++p)
    if (c.model.points.original_position[p][0] > top0) {
      top0 = c.model.points.original_position[p][0];
      top = c.model.points.position[p][0];
    }
  const double penetration = weight / (1000.0 * 80.0 / 0.5);
  const double exact = test::column_closed_form().position(top0) - penetration;
  const double bound = 0.125 * (1.0 - std::exp(-weight / 80.0));
  std::cout << "top point: " << top << ", closed form - penetration " << exact << ", bound " << bound << "\n";
  EXPECT_GT(top, exact - 1e-3);
  EXPECT_LT(top, exact + bound);
}

TEST(RigidBox, TangentIsTheDerivativeOfTheInternalForce) {
  // A plastic block (the F-bar test's) pressed 0.02 by a rigid box over its top left corner.
  const std::string block =
      test::strip_load_case() + "[[rigid_boxes]]\nmin = [-1.0, 1.0]\nmax = [0.3, 2.0]\ndisplacement = [0.0, -0.02]\n";
  CaseFile cf = CaseFile::parse(block, "block.toml", {"load_steps.count=1", "constraints[2].displacement=[0.0,0.0]"});
  MpmCase<2> c = read_mpm_case<2>(cf);
  detail::LoadStep<2> step(c.model, 1.0, 1.0);
  const double rel = test::assembled_tangent_check(step, 1e-4, 5, 1e-8).error;
  const double force = -step.rigid_forces()[1];
  std::cout << "rigid box: contact force " << force << ", max |K - K_fd| / max |K| = " << rel << "\n";
  EXPECT_GT(force, 0.0) << "the box presses";
  EXPECT_LT(rel, 1e-6);
}

TEST(RigidBox, OverlappingAtTheStartIsRefused) {
  const std::string msg = test::read_error<1>(CaseFile::parse(kColumn, "column.toml", {"rigid_boxes[0].max=[0.1]"}));
  EXPECT_NE(msg.find("rigid_boxes[0].min"), std::string::npos) << msg;
  EXPECT_NE(msg.find("overlaps"), std::string::npos) << msg;
}

TEST(RigidBox, FrictionTangentIsTheDerivativeOfTheInternalForce) {
  const std::string block = test::strip_load_case() +
                            "[[rigid_boxes]]\nmin = [-1.0, 1.0]\nmax = [0.3, 2.0]\ndisplacement = [0.01, -0.02]\n"
                            "friction = 0.3\nadhesion = 0.5\n";
  CaseFile cf = CaseFile::parse(block, "block.toml", {"load_steps.count=1", "constraints[2].displacement=[0.0,0.0]"});
  MpmCase<2> c = read_mpm_case<2>(cf);
  EXPECT_FALSE(c.model.symmetric_tangent());
  detail::LoadStep<2> step(c.model, 1.0, 1.0);
  const test::TangentCheck check = test::assembled_tangent_check(step, 1e-4, 5, 1e-8);
  const Vector F = step.rigid_forces();
  std::cout << "rough box: contact force (" << F[0] << ", " << F[1] << "), max |K - K_fd| / max |K| = " << check.error
            << ", asymmetry " << check.asymmetry << "\n";
  EXPECT_GT(std::abs(F[0]), 0.0) << "the box shears the block";
  EXPECT_LT(check.error, 1e-6);
  EXPECT_GT(check.asymmetry, 1e-6) << "sliding couples the shear to the pressure";
}

namespace {
// A 1 x 1 Hencky block on a rigid plane y <= 0 that moves `drag` along x; the nodes above
// the block (y >= 1) held along x; gravity presses the block on the plane. (With nu > 0,
// Poisson's expansion under the weight makes the block's edges slip outward while its
// middle sticks: partial slip, which Newton settles with the line search.)
std::string dragged_block(double drag, double nu = 0.0, const std::string& line_search = "auto") {
  return R"(
[grid]
origin = [-1.0, -1.0]
cell_size = 0.25
cells = [16, 10]
[basis]
type = "gimp"
[materials.a]
model = "hencky"
young = 1.0e4
poisson = )" + std::to_string(nu) + R"(
density = 1.0
[[bodies]]
material = "a"
min = [0.0, 0.0]
max = [1.0, 1.0]
[loads]
gravity = [0.0, -10.0]
[[rigid_boxes]]
name = "plane"
min = [-1.0, -1.0]
max = [2.5, 0.0]
displacement = [)" +
         std::to_string(drag) + R"(, 0.0]
friction = 0.4
[[constraints]]
min = [-1.0, 1.0]
max = [3.0, 1.5]
fix = ["x"]
[load_steps]
count = 4
[nonlinear_solver]
line_search = ")" + line_search + R"("
[output]
vtk_every = 0
)";
}
}  // namespace

TEST(RigidBox, BlockDraggedOnARoughPlaneSlidesAtMuTimesItsPressure) {
  for (const auto& [drag, nu] : {std::pair{0.05, 0.0}, std::pair{1e-6, 0.0}, std::pair{0.05, 0.3}, std::pair{1e-6, 0.3}}) {
    CaseFile cf = CaseFile::parse(dragged_block(drag, nu), "dragged.toml");
    MpmCase<2> c = read_mpm_case<2>(cf);
    double worst = 0.0, largest_ratio = 0.0;
    run_quasi_static<2>(c.model, c.newton, [&](const Model<2>&, const StepInfo& info) {
      const Vector F = info.rigid_forces();  // on the block: (shear, pressure)
      EXPECT_NEAR(F[1], info.load_factor * 10.0, 1e-8 * 10.0) << "the plane carries the weight";
      EXPECT_GT(F[0], 0.0) << "the plane drags the block along";
      worst = std::max(worst, std::abs(F[0] - 0.4 * F[1]) / F[1]);
      largest_ratio = std::max(largest_ratio, F[0] / F[1]);
    });
    std::cout << "drag " << drag << ", nu " << nu << ": shear / pressure up to " << largest_ratio
              << " (mu 0.4), |T - mu N| / N <= " << worst << "\n";
    if (drag > 1e-3) {
      EXPECT_LT(worst, 1e-8);
    } else {  // sticks: the plane's shear is the block's, K drag, carried from step to step
      EXPECT_LT(largest_ratio, 0.2);
      double shear = 0.0;
      for (const auto& t : c.model.points.contact_shear) shear += t[0];
      EXPECT_GT(shear, 0.0) << "the stick's shear is kept for the next step";
    }
  }
}

TEST(RigidBox, PartialSlipNeedsTheLineSearch) {
  // nu = 0.3, drag 1e-6: without the line search Newton's corrections cycle through the
  // points' stick-slip switches (a period of four iterates) and the run stops.
  CaseFile cf = CaseFile::parse(dragged_block(1e-6, 0.3, "off"), "dragged.toml", {"nonlinear_solver.max_cuts=3"});
  MpmCase<2> c = read_mpm_case<2>(cf);
  EXPECT_FALSE(c.newton.line_search);
  EXPECT_THROW(run_quasi_static<2>(c.model, c.newton, [](const Model<2>&, const StepInfo&) {}), SolverError);
  CaseFile on = CaseFile::parse(dragged_block(1e-6, 0.3), "dragged.toml");
  EXPECT_TRUE(read_mpm_case<2>(on).newton.line_search) << "auto: on with a rough box";
}

namespace {
/// The plastic block of R2 with `body` appended, one load step.
MpmCase<2> block_with(const std::string& body, int steps = 1) {
  CaseFile cf = CaseFile::parse(test::strip_load_case() + body, "block.toml",
                                {fmt::format("load_steps.count={}", steps), "constraints[2].displacement=[0.0,0.0]"});
  return read_mpm_case<2>(cf);
}
std::vector<Vector> contact_forces(MpmCase<2> c) {
  std::vector<Vector> F;
  run_quasi_static<2>(c.model, c.newton, [&](const Model<2>&, const StepInfo& info) { F.push_back(info.rigid_forces()); });
  return F;
}
}  // namespace

TEST(RigidBody, PolygonThatIsABoxGivesTheBoxsAnswers) {
  for (const std::string rough : {"", "friction = 0.3\n"}) {
    const std::string move = "displacement = [0.0, -0.03]\n" + rough;
    const std::vector<Vector> box =
        contact_forces(block_with("[[rigid_boxes]]\nmin = [-1.0, 1.0]\nmax = [0.3, 2.0]\n" + move, 4));
    const std::vector<Vector> polygon = contact_forces(block_with(
        "[[rigid_bodies]]\nshape = \"polygon\"\nvertices = [[-1.0, 1.0], [0.3, 1.0], [0.3, 2.0], [-1.0, 2.0]]\n" + move,
        4));
    ASSERT_GE(box.size(), 4u);
    ASSERT_EQ(polygon.size(), box.size()) << "the same steps, cuts and all";
    for (std::size_t k = 0; k < box.size(); ++k) {
      std::cout << (rough.empty() ? "smooth" : "rough") << ", step " << k + 1 << ": box (" << box[k][0] << ", "
                << box[k][1] << "), polygon (" << polygon[k][0] << ", " << polygon[k][1] << ")\n";
      EXPECT_LT((box[k] - polygon[k]).norm(), 1e-12 * box[k].norm()) << "step " << k + 1;
    }
  }
}

TEST(RigidBody, RoughPolygonTangentIsTheDerivativeOfTheInternalForce) {
  // A wedge, its tip at (0.2, 1) on the block's top, pressed 0.02 and moved 0.01 sideways.
  MpmCase<2> c = block_with(
      "[[rigid_bodies]]\nshape = \"polygon\"\nvertices = [[0.2, 1.0], [0.7, 1.5], [-0.3, 1.5]]\n"
      "displacement = [0.01, -0.02]\nfriction = 0.3\nadhesion = 0.5\n");
  detail::LoadStep<2> step(c.model, 1.0, 1.0);
  const test::TangentCheck check = test::assembled_tangent_check(step, 1e-4, 5, 1e-8);
  const Vector F = step.rigid_forces();
  std::cout << "rough wedge: contact force (" << F[0] << ", " << F[1] << "), max |K - K_fd| / max |K| = " << check.error
            << ", asymmetry " << check.asymmetry << "\n";
  EXPECT_LT(F[1], 0.0) << "the wedge presses";
  EXPECT_LT(check.error, 1e-6);
}

TEST(RigidBody, FrictionlessPolygonPushesAlongItsFacesNormal) {
  const std::vector<Vector> F = contact_forces(block_with(
      "[[rigid_bodies]]\nshape = \"polygon\"\nvertices = [[-0.5, 0.95], [1.5, 1.15], [1.5, 2.0], [-0.5, 2.0]]\n"
      "displacement = [0.0, -0.02]\n",
      2));
  ASSERT_EQ(F.size(), 2u);
  for (const Vector& f : F) {
    std::cout << "ramp: force (" << f[0] << ", " << f[1] << "), F_x / F_y = " << f[0] / f[1] << "\n";
    EXPECT_LT(f[1], 0.0);
    EXPECT_NEAR(f[0] / f[1], -0.1, 1e-10);
  }
}

TEST(RigidBody, BadPolygonsAreRefusedNamingTheKey) {
  const std::string head = "[[rigid_bodies]]\nshape = \"polygon\"\n";
  auto error = [&](const std::string& body) {
    return test::read_error<2>(CaseFile::parse(test::strip_load_case() + head + body, "block.toml"));
  };
  std::string msg = error("vertices = [[0.0, 1.5], [1.0, 1.5]]\n");
  EXPECT_NE(msg.find("rigid_bodies[0].vertices: expected at least 3 vertices"), std::string::npos) << msg;
  msg = error("vertices = [[0.0, 1.5], [1.0, 1.5], [0.5, 1.7], [1.0, 2.0], [0.0, 2.0]]\n");
  EXPECT_NE(msg.find("rigid_bodies[0].vertices: expected a convex polygon"), std::string::npos) << msg;
  EXPECT_NE(msg.find("turns the other way"), std::string::npos) << msg;
  msg = error("vertices = [[0.0, 1.5], [0.5, 1.5], [1.0, 1.5], [0.5, 2.0]]\n");
  EXPECT_NE(msg.find("on a line with its neighbours"), std::string::npos) << msg;
  msg = error("vertices = [[0.5, 0.5], [1.5, 0.5], [1.0, 1.5]]\n");
  EXPECT_NE(msg.find("rigid_bodies[0].vertices: expected a body that no material point's domain overlaps"),
            std::string::npos)
      << msg;
}
