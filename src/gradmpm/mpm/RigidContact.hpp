#pragma once
// Rigid bodies that push material points by penalty contact, frictionless or with Coulomb
// friction and adhesion: a rigid footing, a platen, an indenter, a shaft, a cone. A body
// is an axis-aligned box, or in 2D a convex polygon. A footing held on a row of grid nodes
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
// A convex polygon and a domain (a box) overlap unless an axis separates them (the
// separating axis theorem): the axes are the polygon's face normals and the grid's. The
// push-out along each is the overlap of their projections, and the smallest wins: along
// a face normal n, g = c - n . x_p + sum_i l_i |n_i| (c = n . a vertex of the face);
// along the grid's axes, the box's own push-outs against the polygon's bounding box. Every
// g is linear in x_p with dg/dx_p = -n, so the tangent keeps its form; A_p across a face
// normal is the domain's width along the face, 2 (l_x |n_y| + l_y |n_x|).
//
// Friction (RigidBox::friction mu, adhesion a): the tangential force T on the point is the
// last step's (MaterialPoints::contact_shear) less k A_p times the point's slip against
// the box over the step (a stick spring as stiff as the normal one), returned to the
// Coulomb-Tresca limit |T| <= a A_p + mu k A_p g when it exceeds it: sliding, T along the
// trial's direction. Its tangent: stick, k A_p N_a N_b on the tangential components;
// slide, k A_p (limit / |T_trial|) (I - d d^T) N_a N_b there and mu k A_p sign d N_a N_b
// from the tangential rows to the normal column (the pressure sets the limit): not
// symmetric. Axisymmetric (Model::axisymmetric): A_p is per radian, times r_p.
#include <cmath>
#include <limits>
#include <tuple>
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
  /// The boxes where the step ends (lambda_end), having moved dlambda of their travel.
  RigidContact(const std::vector<RigidBox<dim>>& boxes, const MaterialPoints<dim>& pts, const PointStencils<dim>& st,
               const DofMap& dofs, double lambda_end, double dlambda, bool axisymmetric)
      : boxes_(boxes),
        pts_(pts),
        st_(st),
        dofs_(dofs),
        axisymmetric_(axisymmetric),
        force_(boxes.size(), Vec<dim>::Zero()),
        faces_(boxes.size()) {
    for (std::size_t b = 0; b < boxes.size(); ++b) {
      const RigidBox<dim>& box = boxes[b];
      lo_.push_back(box.lo + lambda_end * box.total);
      hi_.push_back(box.hi + lambda_end * box.total);
      moved_.push_back(dlambda * box.total);
      any_frictional_ = any_frictional_ || box.friction > 0.0 || box.adhesion > 0.0;
      faces_[b] = polygon_faces(box, lambda_end);
    }
  }

  /// A polygon's faces at load factor lambda: outward normal n and c = n . x on the face.
  struct Face {
    Vec<dim> normal;
    double offset;
  };
  static std::vector<Face> polygon_faces(const RigidBox<dim>& box, double lambda) {
    std::vector<Face> faces;
    const auto& v = box.polygon;
    if constexpr (dim == 2)
      for (std::size_t k = 0; k < v.size(); ++k) {
        const Vec<dim> a = v[k] + lambda * box.total, e = v[(k + 1) % v.size()] - v[k];
        const Vec<dim> n = Vec<dim>(e[1], -e[0]).normalized();  // (anticlockwise: outward)
        faces.push_back({n, n.dot(a)});
      }
    return faces;
  }
  /// The push-out of a domain (centre x, half-lengths l) along a face's normal: its overlap
  /// with the polygon across the face (< 0: the face separates them).
  static double face_push(const Face& f, const Vec<dim>& x, const Vec<dim>& l) {
    return f.offset - (f.normal.dot(x) - l.dot(f.normal.cwiseAbs()));
  }

  /// Finds the contacts at the iterate du and adds -sum_p N_a F_p to f_int (the boxes act
  /// on the body like an external force that depends on its motion).
  void add_force(const Vector& du, Vector& f_int) {
    // The sliding directions of the last iterate, for sliding() (frictional boxes only)
    if (any_frictional_) {
      previous_.assign(pts_.size(), Vec<dim>::Zero());
      for (const Contact& c : contacts_)
        if (c.slides) previous_[c.point] = c.direction;
    }
    contacts_.clear();
    for (auto& f : force_) f.setZero();
    for (int p = 0; p < pts_.size(); ++p) {
      const Stencil<dim>& s = st_[p];
      Vec<dim> x = pts_.position[p], dx = Vec<dim>::Zero();  // (x summed onto x_n, as ever: the same bits)
      for (int a = 0; a < s.count; ++a)
        for (int i = 0; i < dim; ++i) {
          const double u = s.N[a] * du[dofs_.dof(s.node[a], i)];
          x[i] += u;
          dx[i] += u;
        }
      const Vec<dim>& l = pts_.half_length[p];
      for (std::size_t b = 0; b < boxes_.size(); ++b) {
        Contact c;
        c.point = p;
        c.box = static_cast<int>(b);
        c.gap = std::numeric_limits<double>::infinity();
        bool inside = true;
        double sign = 0.0;
        for (int e = 0; e < dim && inside; ++e) {
          const double up = hi_[b][e] - (x[e] - l[e]), down = (x[e] + l[e]) - lo_[b][e];  // push-outs along +e, -e
          inside = up >= 0.0 && down >= 0.0;  // touching counts: its stiffness holds a body resting on the box
          if (up < c.gap) std::tie(c.axis, sign, c.gap) = std::make_tuple(e, 1.0, up);
          if (down < c.gap) std::tie(c.axis, sign, c.gap) = std::make_tuple(e, -1.0, down);
        }
        if (inside) c.normal = sign * Vec<dim>::Unit(c.axis);
        for (std::size_t f = 0; f < faces_[b].size() && inside; ++f) {  // a polygon's faces
          const double push = face_push(faces_[b][f], x, l);
          inside = push >= 0.0;
          if (push < c.gap) std::tie(c.axis, c.normal, c.gap) = std::make_tuple(-1, faces_[b][f].normal, push);
        }
        if (!inside) continue;
        double area = axisymmetric_ ? pts_.position[p][0] : 1.0;  // (per radian)
        if (c.axis >= 0) {
          for (int e = 0; e < dim; ++e)
            if (e != c.axis) area *= 2.0 * l[e];
        } else if constexpr (dim == 2) {
          area *= 2.0 * (l[0] * std::abs(c.normal[1]) + l[1] * std::abs(c.normal[0]));
        }
        c.k_area = boxes_[b].stiffness * area;
        const double F = c.k_area * c.gap;  // on the point, along the normal
        force_[b] += F * c.normal;
        for (int i = 0; i < dim; ++i)
          if (c.normal[i] != 0.0)
            for (int a = 0; a < s.count; ++a) f_int[dofs_.dof(s.node[a], i)] -= s.N[a] * (F * c.normal[i]);
        if (frictional(b)) add_shear(c, area, dx, f_int);
        contacts_.push_back(c);
      }
    }
  }

  /// K += k A N_a N_b on the contact axis, and the frictional terms, for the contacts of
  /// the last add_force.
  void add_matrix(SparseMatrix& K) const {
    double* values = K.valuePtr();
    for (const Contact& c : contacts_) {
      const Stencil<dim>& s = st_[c.point];
      // d(-N_a T_i) / d du_(b j) = N_a N_b M(i, j): the contact's block, its nodes' products aside
      const Vec<dim>& n = c.normal;
      Eigen::Matrix<double, dim, dim> M = c.k_area * n * n.transpose();
      if (frictional(c.box)) {
        const Eigen::Matrix<double, dim, dim> P = Eigen::Matrix<double, dim, dim>::Identity() - n * n.transpose();
        if (sliding(c))  // the limit grows with the pressure: d g / d x = -n
          M += c.k_area * (c.ratio * (P - c.direction * c.direction.transpose()) +
                           boxes_[c.box].friction * c.direction * n.transpose());
        else
          M += c.k_area * P;
      }
      for (int b = 0; b < s.count; ++b)
        for (int j = 0; j < dim; ++j) {
          const int col = dofs_.dof(s.node[b], j);
          for (int i = 0; i < dim; ++i) {
            if (M(i, j) == 0.0) continue;
            for (int a = 0; a < s.count; ++a)
              values[pattern_offset(K, dofs_.dof(s.node[a], i), col)] += M(i, j) * s.N[a] * s.N[b];
          }
        }
    }
  }

  /// At the converged iterate: each point's tangential force for the next step (zero for
  /// the points out of a frictional contact).
  void store_shear(std::vector<Vec<dim>>& shear) const {
    for (auto& t : shear) t.setZero();
    for (const Contact& c : contacts_)
      if (frictional(c.box)) shear[c.point] = c.shear;
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
    int point = 0, box = 0;
    int axis = 0;                        ///< the grid axis of the normal; -1: a polygon's face normal
    Vec<dim> normal = Vec<dim>::Zero();  ///< outward from the body, the push-out's direction
    double gap = 0.0, k_area = 0.0;
    Vec<dim> shear = Vec<dim>::Zero();      ///< T on the point (friction)
    bool slides = false;                    ///< T at the limit
    double ratio = 0.0;                     ///< limit / |T_trial| when sliding
    Vec<dim> direction = Vec<dim>::Zero();  ///< T_trial / |T_trial| when sliding
  };

  bool frictional(int b) const { return boxes_[b].friction > 0.0 || boxes_[b].adhesion > 0.0; }
  /// Whether contact c takes the sliding tangent (else the stick one): it slides with a
  /// limit above zero, the way it slid at the last iterate if it did. The sliding tangent
  /// has no tangential stiffness in 2D, so a Newton step from a sliding iterate carries
  /// the point as far as the body lets it, past a stick that holds it: the next iterate
  /// slides back, and Newton swung from side to side for good (a block on a slowly
  /// dragged plane). A contact that turns, or only touches (no pressure, no adhesion: the
  /// limit is zero, as at a step's first iterate for every point resting on a box), takes
  /// the stick tangent; Newton then finds the stick, or the slide the iterate after.
  bool sliding(const Contact& c) const {
    return c.slides && c.ratio > 0.0 && (previous_.empty() || previous_[c.point].dot(c.direction) >= 0.0);
  }

  /// The tangential force of contact c at the point's step displacement dx, into c, the
  /// box's force and f_int.
  void add_shear(Contact& c, double area, const Vec<dim>& dx, Vector& f_int) {
    const RigidBox<dim>& box = boxes_[c.box];
    const Vec<dim>& n = c.normal;
    Vec<dim> T = pts_.contact_shear[c.point];  // the last step's, in this contact's plane
    T -= n * n.dot(T);
    Vec<dim> slip = dx - moved_[c.box];
    slip -= n * n.dot(slip);
    T -= c.k_area * slip;  // the stick spring against the slip
    const double limit = box.adhesion * area + box.friction * c.k_area * c.gap, size = T.norm();
    c.slides = size > limit;
    if (c.slides) {
      c.direction = T / size;
      c.ratio = limit / size;
      T *= c.ratio;
    }
    c.shear = T;
    force_[c.box] += T;
    const Stencil<dim>& s = st_[c.point];
    for (int a = 0; a < s.count; ++a)
      for (int j = 0; j < dim; ++j)
        if (T[j] != 0.0) f_int[dofs_.dof(s.node[a], j)] -= s.N[a] * T[j];
  }
  const std::vector<RigidBox<dim>>& boxes_;
  const MaterialPoints<dim>& pts_;
  const PointStencils<dim>& st_;
  const DofMap& dofs_;
  const bool axisymmetric_;
  bool any_frictional_ = false;  ///< a box has friction or adhesion (the iterates' sliding directions are kept)
  std::vector<Vec<dim>> lo_, hi_, moved_, force_;
  std::vector<std::vector<Face>> faces_;  ///< per body: a polygon's faces at the step's end (none for a box)
  std::vector<Contact> contacts_;
  std::vector<Vec<dim>> previous_;  ///< per point: its sliding direction at the iterate before (zero: none)
};

}  // namespace gradmpm
