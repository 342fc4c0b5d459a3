#pragma once
// Small-strain linear elasticity, the classical law C_ijkl of eq. (4)-(6).
// In 1D (a bar) the law is sigma = E eps with tangent E. Later materials (Hencky,
// plasticity) join with the same two questions: stress from strain, and tangent.
namespace gradmpm {

struct LinearElastic1D {
  double young = 1.0;
  double stress(double strain) const { return young * strain; }
  double tangent() const { return young; }
};

}  // namespace gradmpm
