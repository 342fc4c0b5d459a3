#pragma once
// The biaxial test's runs and the measure of its shear band (examples/biaxial_2d.toml;
// test_shear_band_2d.cpp states the requirements, test_shear_band_coarse.cpp guards them fast).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "gradmpm/app/MpmCase.hpp"
#include "gradmpm/core/Errors.hpp"

namespace gradmpm::test {

inline const std::string kExample = std::string(GRADMPM_SOURCE_DIR) + "/examples/biaxial_2d.toml";
constexpr double kL = 1.0 / 12.0;   // the example's length scale
constexpr double kPlaten = 0.0125;  // the platen displacement the bands are compared at
constexpr int kSteps = 50;          // the example's step size, 0.075 / 300

struct Band {
  double angle = 0.0;      ///< degrees between the band and the loading (vertical) axis
  double thickness = 0.0;  ///< mean normal thickness where eps_p > half the section's peak
  double spread = 0.0;     ///< its standard deviation over the sections
  double peak = 0.0;       ///< the largest eps_p of the sections
  int sections = 0;
};

/// eps_p of every point, by the name its material gives it.
inline std::vector<double> eps_p_of(const Model<2>& m) {
  std::vector<int> offset(m.materials.size(), -1);
  for (std::size_t k = 0; k < m.materials.size(); ++k) {
    int o = 0;
    for (const auto& v : m.materials[k]->state_variables()) {
      if (v.name == "eps_p") offset[k] = o;
      o += v.size();
    }
  }
  std::vector<double> e(m.points.size(), 0.0);
  for (int p = 0; p < m.points.size(); ++p) {
    const int o = offset[m.points.material[p]];
    if (o >= 0) e[p] = m.points.state[p * m.points.state_stride + o];
  }
  return e;
}

/// The band measured in horizontal sections one point row apart (`spacing`) with centres
/// from y = 0.25 to 0.75, where it crosses the specimen clear of the weak corner and the
/// far side: in each, the x where eps_p first and last exceeds half the section's peak
/// (linear between points); the band's centre line is fitted through the midpoints.
inline Band measure(const Model<2>& m, double spacing) {
  const std::vector<double> e = eps_p_of(m);
  std::vector<double> yc, xc, width;
  Band b;
  for (double y0 = 0.25; y0 <= 0.75 + 1e-9; y0 += spacing) {
    std::vector<std::pair<double, double>> row;  // (x, eps_p)
    for (int p = 0; p < m.points.size(); ++p)
      if (std::abs(m.points.position[p][1] - y0) < spacing / 2) row.push_back({m.points.position[p][0], e[p]});
    if (row.size() < 5) continue;
    std::sort(row.begin(), row.end());
    const auto top = std::max_element(row.begin(), row.end(), [](auto& a, auto& c) { return a.second < c.second; });
    const std::size_t k = top - row.begin();
    const double half = top->second / 2;
    std::size_t i = k, j = k;
    while (i > 0 && row[i - 1].second > half) --i;
    while (j + 1 < row.size() && row[j + 1].second > half) ++j;
    if (i == 0 || j + 1 == row.size()) continue;  // the band reaches the section's end
    auto cross = [&](std::size_t a, std::size_t c) {
      return row[a].first + (half - row[a].second) / (row[c].second - row[a].second) * (row[c].first - row[a].first);
    };
    const double left = cross(i - 1, i), right = cross(j, j + 1);
    yc.push_back(y0);
    xc.push_back(0.5 * (left + right));
    width.push_back(right - left);
    b.peak = std::max(b.peak, top->second);
  }
  b.sections = static_cast<int>(yc.size());
  if (b.sections < 3) return b;
  // least-squares line x = a + s y through the section midpoints
  const double n = b.sections;
  double sy = 0, sx = 0, syy = 0, sxy = 0;
  for (int k = 0; k < b.sections; ++k) {
    sy += yc[k];
    sx += xc[k];
    syy += yc[k] * yc[k];
    sxy += yc[k] * xc[k];
  }
  const double slope = (n * sxy - sy * sx) / (n * syy - sy * sy);
  b.angle = std::atan(slope) * 180.0 / std::numbers::pi;
  const double c = std::cos(std::atan(slope));
  double sum = 0, sum2 = 0;
  for (double w : width) {
    sum += w * c;
    sum2 += w * c * w * c;
  }
  b.thickness = sum / n;
  b.spread = std::sqrt(std::max(0.0, sum2 / n - b.thickness * b.thickness));
  return b;
}

struct BiaxialRun {
  Band band;
  double h = 0.0, force = 0.0;
  bool failed = false;
  std::string why;
};

struct ForceReached {};  // thrown by the observer to end a run at a force (S4)

/// The example on cells of h = 1 / (24 r) (the example's is r = 1), its platen moved by
/// `platen` in the example's step size; with length scale l (and weak patch l x l). With
/// stop_force > 0 the run ends at the first step past the peak whose force is below it.
inline BiaxialRun run_biaxial(double r, bool regularised, double l = kL, double platen = kPlaten, double stop_force = 0.0) {
  const double h = 1.0 / (24.0 * r);
  std::vector<std::string> set{fmt::format("grid.origin=[-0.25,{}]", -2 * h),
                               fmt::format("grid.cell_size={}", h),
                               fmt::format("grid.cells=[{},{}]", std::lround(36 * r), std::lround(52 * r + 2)),
                               fmt::format("rigid_boxes[0].displacement=[0.0,{}]", -platen),
                               fmt::format("load_steps.count={}", std::lround(platen / kPlaten * kSteps)),
                               "output.vtk_every=0"};
  if (l != kL) {
    set.push_back(fmt::format("regularisation.length_scale={}", l));
    set.push_back(fmt::format("bodies[0].max=[{0},{0}]", l));
    set.push_back(fmt::format("bodies[1].polygon=[[{0},0.0],[1.0,0.0],[1.0,2.0],[0.0,2.0],[0.0,{0}],[{0},{0}]]", l));
  }
  CaseFile cf = CaseFile::load(kExample, set);
  if (!regularised) cf.remove_section("regularisation");
  MpmCase<2> c = read_mpm_case<2>(cf);
  BiaxialRun out;
  out.h = h;
  double peak = 0.0;
  try {
    run_quasi_static<2>(c.model, c.newton, [&](const Model<2>&, const StepInfo& info) {
      const Vector f = info.rigid_forces();
      out.force = -f[1];
      peak = std::max(peak, out.force);
      if (stop_force > 0.0 && out.force < stop_force && out.force < peak) throw ForceReached{};
    });
    if (stop_force > 0.0) {
      out.failed = true;
      out.why = fmt::format("the force did not fall to {} by platen {}", stop_force, platen);
    }
  } catch (const ForceReached&) {
  } catch (const SolverError& e) {
    out.failed = true;
    out.why = e.what();
  }
  out.band = measure(c.model, h / 2);
  fmt::print(
      "{}, l = {:.4f}, h = l/{:.0f}: {} platen force {:.4f} (peak {:.4f}); band at {:.2f} deg, thickness {:.4f} "
      "({:.2f} l, {:.2f} h) +- {:.4f} over {} sections, peak eps_p {:.4f}\n",
      regularised ? "regularised" : "classical", l, l / h, out.failed ? "FAILED (" + out.why + ")," : "", out.force,
      peak, out.band.angle, out.band.thickness, out.band.thickness / l, out.band.thickness / h, out.band.spread,
      out.band.sections, out.band.peak);
  return out;
}

}  // namespace gradmpm::test
