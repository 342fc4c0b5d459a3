// bench_bar: cost of the 1D bi-material bar as the mesh grows.
//
// For each size it prints the dofs, points and nonzeros, the seconds spent in assembly
// (point generation, shape functions, pattern, stiffness), in the classical solve
// (CHOLMOD analysis + factorisation + solve) and in the gradient step (assembly and
// factorisation of M + l^2 L, smoothing solve) and in recovery (nodal values, the
// displacement that e-RA integrates from its strain), and the ratio of the gradient
// step to the classical solve. Run:  build/bench/bench_bar [max_elements]
#include <fmt/format.h>

#include <cstdlib>

#include "gradmpm/app/BarProblem.hpp"

int main(int argc, char** argv) {
  const long max_elements = argc > 1 ? std::atol(argv[1]) : 1'000'000;
  fmt::print("{:>8} {:>9} {:>9} {:>6} {:>11} {:>11} {:>11} {:>11} {:>9}\n", "variant", "dofs", "points", "nnz",
             "assembly_s", "classical_s", "gradient_s", "recovery_s", "grad/cls");
  for (auto variant : {gradmpm::GradientVariant::U_RA, gradmpm::GradientVariant::E_RA}) {
    for (long n = 1000; n <= max_elements; n *= 10) {
      gradmpm::BarConfig c;
      c.elements = static_cast<int>(n);
      c.variant = variant;
      const gradmpm::BarResult r = gradmpm::solve_bar(c);
      const long nnz = 3L * r.dofs - 2;  // tridiagonal in 1D
      fmt::print("{:>8} {:>9} {:>9} {:>6.2g} {:>11.4f} {:>11.4f} {:>11.4f} {:>11.4f} {:>9.2f}\n",
                 gradmpm::to_string(variant), r.dofs, r.points.size(), static_cast<double>(nnz), r.timings.assembly_s,
                 r.timings.classical_solve_s, r.timings.gradient_s, r.timings.recovery_s,
                 r.timings.gradient_s / r.timings.classical_solve_s);
    }
  }
}
