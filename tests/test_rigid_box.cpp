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
//     sideways, gravity pressing it down): sliding, the plane's shear on it is mu times
//     its pressure to 1e-8 at every step; a drag too small to overcome the friction
//     sticks (shear below half of mu N), and the stick carries over from step to step.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <iostream>

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
// the block (y >= 1) held along x; gravity presses the block on the plane. (nu = 0: with
// Poisson's expansion under the weight the block's edges slip outward while its middle
// sticks, and Newton did not settle that partial slip at drag 1e-6; docs/plasticity.md.)
std::string dragged_block(double drag) {
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
poisson = 0.0
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
[output]
vtk_every = 0
)";
}
}  // namespace

TEST(RigidBox, BlockDraggedOnARoughPlaneSlidesAtMuTimesItsPressure) {
  for (const double drag : {0.05, 1e-6}) {
    CaseFile cf = CaseFile::parse(dragged_block(drag), "dragged.toml");
    MpmCase<2> c = read_mpm_case<2>(cf);
    double worst = 0.0, largest_ratio = 0.0;
    run_quasi_static<2>(c.model, c.newton, [&](const Model<2>&, const StepInfo& info) {
      const Vector F = info.rigid_forces();  // on the block: (shear, pressure)
      EXPECT_NEAR(F[1], info.load_factor * 10.0, 1e-8 * 10.0) << "the plane carries the weight";
      EXPECT_GT(F[0], 0.0) << "the plane drags the block along";
      worst = std::max(worst, std::abs(F[0] - 0.4 * F[1]) / F[1]);
      largest_ratio = std::max(largest_ratio, F[0] / F[1]);
    });
    std::cout << "drag " << drag << ": shear / pressure up to " << largest_ratio << " (mu 0.4), |T - mu N| / N <= "
              << worst << "\n";
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
