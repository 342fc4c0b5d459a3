#pragma once
// Case-file texts shared by several tests.
#include <fmt/format.h>

#include <cmath>
#include <string>

namespace gradmpm::test {

/// The bi-material plate in tension: 1 x 0.25, E = 1000 | 5000 (nu = 0), cells
/// of h and one cell of margin, the right edge pulled by 1e-3 in one load step, e-RA with
/// length scale l at the end.
inline std::string bimaterial_plate(double h, double l) {
  const int nx = static_cast<int>(std::lround(1.0 / h)), ny = static_cast<int>(std::lround(0.25 / h));
  return fmt::format(R"(
[grid]
origin = [{0}, {0}]
cell_size = {1}
cells = [{2}, {3}]
[materials.soft]
model = "linear-elastic"
young = 1000.0
[materials.stiff]
model = "linear-elastic"
young = 5000.0
[[bodies]]
material = "soft"
min = [0.0, 0.0]
max = [0.5, 0.25]
[[bodies]]
material = "stiff"
min = [0.5, 0.0]
max = [1.0, 0.25]
[[constraints]]
min = [{0}, {0}]
max = [0.0, 1.0]
fix = ["x"]
[[constraints]]
min = [{0}, {0}]
max = [2.0, 0.0]
fix = ["y"]
[[constraints]]
min = [1.0, {0}]
max = [2.0, 1.0]
fix = ["x"]
displacement = [0.001, 0.0]
[load_steps]
count = 1
[gradient]
variant = "e-RA"
length_scale = {4}
apply = "end"
)",
                     -h, h, nx + 2, ny + 2, l);
}

}  // namespace gradmpm::test
