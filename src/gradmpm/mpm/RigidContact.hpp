#pragma once
// Rigid, frictionless, axis-aligned boxes that push material points by penalty contact: a
// rigid footing, a platen, an indenter. A footing held on a row of grid nodes
// ([[constraints]]) loses its grip on the material once that has moved half a cell away
// from the row (the nodes then reach the points only through the edge of their supports);
// a box acting on the points themselves follows the material to any depth.
//
// A point's domain (the GIMP box x_p +- l_p, at the current iterate x_p + sum_a N_a du_a)
// that overlaps or touches the box is pushed out through the nearest face: penetration g
// along that face's outward normal n, contact force F_p = k A_p g n on the point (A_p the
// point's domain face area across n, k = penalty per unit area and penetration), applied
// to the grid through N_a(x_p). The contact stiffness k A_p N_a N_b (n (x) n) is symmetric
// and lives in the point's stencil, so the sparsity pattern does not change.
#include <limits>
#include <vector>

#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/mpm/Model.hpp"
#include "gradmpm/points/Transfer.hpp"
#include "gradmpm/solver/DofMap.hpp"
#include "gradmpm/solver/SparsePattern.hpp"

namespace gradmpm {

/// The contacts of one load step's iterate.
template <int dim>
class RigidContact {
 public:
  RigidContact(const std::vector<RigidBox<dim>>& boxes, const MaterialPoints<dim>& pts, const PointStencils<dim>& st,
               const DofMap& dofs, double lambda_end)
      : boxes_(boxes), pts_(pts), st_(st), dofs_(dofs), force_(boxes.size(), Vec<dim>::Zero()) {
    for (const auto& b : boxes) {
      lo_.push_back(b.lo + lambda_end * b.total);
      hi_.push_back(b.hi + lambda_end * b.total);
    }
  }

  /// Finds the contacts at the iterate du and adds -sum_p N_a F_p to f_int (the boxes act
  /// on the body like an external force that depends on its motion).
  void add_force(const Vector& du, Vector& f_int) {
    contacts_.clear();
    for (auto& f : force_) f.setZero();
    for (int p = 0; p < pts_.size(); ++p) {
      const Stencil<dim>& s = st_[p];
      Vec<dim> x = pts_.position[p];
      for (int a = 0; a < s.count; ++a)
        for (int i = 0; i < dim; ++i) x[i] += s.N[a] * du[dofs_.dof(s.node[a], i)];
      const Vec<dim>& l = pts_.half_length[p];
      for (std::size_t b = 0; b < boxes_.size(); ++b) {
        Contact c{p, static_cast<int>(b), 0, 0.0, std::numeric_limits<double>::infinity(), 0.0};
        bool inside = true;
        for (int e = 0; e < dim && inside; ++e) {
          const double up = hi_[b][e] - (x[e] - l[e]), down = (x[e] + l[e]) - lo_[b][e];  // push-outs along +e, -e
          inside = up >= 0.0 && down >= 0.0;  // touching counts: its stiffness holds a body resting on the box
          if (up < c.gap) c = {p, static_cast<int>(b), e, 1.0, up, 0.0};
          if (down < c.gap) c = {p, static_cast<int>(b), e, -1.0, down, 0.0};
        }
        if (!inside) continue;
        double area = 1.0;
        for (int e = 0; e < dim; ++e)
          if (e != c.axis) area *= 2.0 * l[e];
        c.k_area = boxes_[b].stiffness * area;
        const double F = c.sign * c.k_area * c.gap;  // on the point, along axis
        force_[b][c.axis] += F;
        for (int a = 0; a < s.count; ++a) f_int[dofs_.dof(s.node[a], c.axis)] -= s.N[a] * F;
        contacts_.push_back(c);
      }
    }
  }

  /// K += k A N_a N_b on the contact axis, for the contacts of the last add_force.
  void add_matrix(SparseMatrix& K) const {
    double* values = K.valuePtr();
    for (const Contact& c : contacts_) {
      const Stencil<dim>& s = st_[c.point];
      for (int b = 0; b < s.count; ++b) {
        const int col = dofs_.dof(s.node[b], c.axis);
        for (int a = 0; a < s.count; ++a)
          values[pattern_offset(K, dofs_.dof(s.node[a], c.axis), col)] += c.k_area * s.N[a] * s.N[b];
      }
    }
  }

  /// The force box b exerts on the body at the last add_force (per unit thickness in 2D);
  /// of this rank's points in a distributed run until sum_forces_over_ranks().
  const Vec<dim>& force(int b) const { return force_[b]; }
  /// A distributed run's: the boxes' forces on every rank's points (a collective call).
  void sum_forces_over_ranks() {
    for (auto& f : force_) ranks::sum(f.data(), dim);
  }

 private:
  struct Contact {
    int point, box, axis;
    double sign, gap, k_area;
  };
  const std::vector<RigidBox<dim>>& boxes_;
  const MaterialPoints<dim>& pts_;
  const PointStencils<dim>& st_;
  const DofMap& dofs_;
  std::vector<Vec<dim>> lo_, hi_, force_;
  std::vector<Contact> contacts_;
};

}  // namespace gradmpm
