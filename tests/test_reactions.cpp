// Requirements on reaction forces (named [[constraints]] blocks, reactions.csv):
//  R1 under self-weight the base carries the weight: ry(base) = -sum_p m_p g lambda at
//     every step, to the Newton tolerance;
//  R2 every force is balanced: with no body force the reactions of all named blocks of a
//     strip load on a plastic block (disjoint node sets holding every constrained node)
//     sum to zero, and the footing's mean displacement is the prescribed settlement;
//  R3 reactions.csv has one row per converged step and named block, and
//     load_displacement.png is written; names are checked.
#include <gtest/gtest.h>
#include <unistd.h>

#include <fmt/format.h>
#include <cmath>
#include <sstream>

#include "CliTestUtil.hpp"
#include "MpmTestUtil.hpp"
#include "PlasticityTestUtil.hpp"
#include "gradmpm/app/MpmCase.hpp"
#include "gradmpm/core/Errors.hpp"

using namespace gradmpm;
namespace fs = std::filesystem;

namespace {
struct Row {
  int step;
  double load;
  std::string name;
  double r[3], u[3];
};
std::vector<Row> read_reactions(const fs::path& file) {
  std::istringstream in(test::slurp(file));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "step,load,name,rx,ry,rz,ux,uy,uz");
  std::vector<Row> rows;
  while (std::getline(in, line)) {
    Row r;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream s(line);
    s >> r.step >> r.load >> r.name >> r.r[0] >> r.r[1] >> r.r[2] >> r.u[0] >> r.u[1] >> r.u[2];
    rows.push_back(r);
  }
  return rows;
}

fs::path scratch(const char* what) {
  const fs::path d = fs::temp_directory_path() / fmt::format("gradmpm-{}-{}", what, ::getpid());
  fs::remove_all(d);
  return d;
}
}  // namespace

TEST(Reactions, TheBaseCarriesTheWeightOfAColumn) {
  const fs::path src = fs::path(GRADMPM_SOURCE_DIR) / "examples" / "column_2d.toml";
  CaseFile cf = CaseFile::load(src, {"constraints[0].name=base", "output.plot=false", "output.check="});
  MpmCase<2> c = read_mpm_case<2>(cf);
  double weight = 0.0;
  for (double mp : c.model.points.mass) weight += mp * -c.model.gravity[1];
  const fs::path dir = scratch("reactions-column");
  CaseFile cf2 = CaseFile::load(src, {"constraints[0].name=base", "output.plot=false", "output.check="});
  run_mpm_case(cf2, dir, true);
  const auto rows = read_reactions(dir / "reactions.csv");
  ASSERT_EQ(rows.size(), static_cast<std::size_t>(c.newton.load_steps));
  for (const auto& r : rows) {
    EXPECT_EQ(r.name, "base");
    EXPECT_NEAR(r.r[1], weight * r.load, 1e-7 * weight) << "step " << r.step;
    EXPECT_NEAR(r.u[1], 0.0, 1e-15) << "the base is held";
  }
  fs::remove_all(dir);
}

namespace {
/// The strip load of the plasticity tests, perfectly plastic, its three constraint blocks
/// named; the side block leaves out the corner nodes, so the named sets are disjoint.
CaseFile named_strip(std::vector<std::string> sets = {}) {
  for (const char* s : {"constraints[0].name=base", "constraints[1].name=side", "constraints[1].min=[0.0, 0.125]",
                        "constraints[1].max=[0.0, 0.875]", "constraints[2].name=footing"})
    sets.insert(sets.begin(), s);
  return CaseFile::parse(
      test::strip_load_case("model = \"von-mises\"\nyoung = 1000.0\npoisson = 0.3\nyield_stress = 10.0\n"),
      "strip.toml", sets);
}
}  // namespace

TEST(Reactions, AllReactionsBalanceAndTheFootingSettlesAsPrescribed) {
  const fs::path dir = scratch("reactions-strip");
  CaseFile cf = named_strip();
  run_mpm_case(cf, dir, true);
  const auto rows = read_reactions(dir / "reactions.csv");
  ASSERT_EQ(rows.size(), 3u * 8u);
  for (int step = 1; step <= 8; ++step) {
    double sum[2] = {0, 0}, scale = 0.0;
    for (const auto& r : rows)
      if (r.step == step) {
        for (int d = 0; d < 2; ++d) sum[d] += r.r[d];
        if (r.name == "footing") {
          scale = std::abs(r.r[1]);
          EXPECT_NEAR(r.u[1], -0.04 * r.load, 1e-14) << "step " << step;
          EXPECT_LT(r.r[1], 0.0) << "the soil pushes the footing up: reaction f_int - f_ext < 0 in y";
        }
      }
    EXPECT_LT(std::abs(sum[0]), 1e-7 * scale) << "step " << step;
    EXPECT_LT(std::abs(sum[1]), 1e-7 * scale) << "step " << step;
  }
  EXPECT_TRUE(fs::exists(dir / "load_displacement.png"));
  fs::remove_all(dir);
}

TEST(Reactions, NamesAreChecked) {
  const std::string error = test::read_error<2>(named_strip({"constraints[0].name=\"a,b\""}));
  EXPECT_NE(error.find("constraints[0].name (from --set): expected a name without commas"), std::string::npos) << error;
}
