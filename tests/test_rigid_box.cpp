// Requirements on rigid boxes (mpm/RigidContact.hpp, [[rigid_boxes]]):
//  R1 a column resting on a rigid box (no grid constraint below it) is carried by the box:
//     its contact force equals the weight at every step (1e-8), the column's top settles
//     by the closed form of the Hencky column plus the penetration q / k, to within what
//     the bottom point's (uGIMP, fixed-size) domain does not follow of the compression, and
//     Newton converges quadratically with the contact;
//  R2 the tangent with active contacts is the derivative of the internal force (central
//     differences, 1e-6 relative);
//  R3 a box that overlaps the points at the start is refused, naming the key.
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
