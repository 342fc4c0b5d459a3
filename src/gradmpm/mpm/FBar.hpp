#pragma once
// The F-bar method for the implicit MPM (Coombs, Charlton, Cortis & Augarde 2018,
// "Overcoming volumetric locking in material point methods", CMAME 333), against the
// volumetric locking of isochoric plastic flow: the points of one background cell share
// one volume change per load step,
//   dJbar_c = sum_{q in c} w_q dJ_q,   w_q = v_q,n / sum_{q in c} v_q,n,
//   dFbar_p = (dJbar_c / dJ_p)^(1/dim) dF_p   (the in-plane block in plane strain; the
//             whole of it, 1/3, when axisymmetric: the hoop stretch changes the volume),
// the material is updated with dFbar, sigma = tau(Fbar) / Jbar, and f_int integrates sigma
// over the actual current volumes. Linearising (de Souza Neto et al. 2008, sec. 15.4, with
// the cell average in place of the centroid) gives the tangent
//   K = sum_p W_p G_a [A - Q (x) I] G_b  +  sum_c (sum_{p in c} W_p G_pa Q_p) (x) (sum_{q in c} beta_q G_qb),
//   Q_ij = (1/dim) A_ijmm - (1 - 1/dim) tau_ij,  beta_q = w_q dJ_q / dJbar_c,
//   W_p = (v_p,n / Jbar_p,n) dJ_p / dJbar_c, G = grad_n N dF^-1,
// non-symmetric (solved as such) and coupling all nodes of a cell's points.
#include <algorithm>
#include <array>
#include <map>
#include <vector>

#include "gradmpm/grid/Grid.hpp"
#include "gradmpm/points/MaterialPoints.hpp"
#include "gradmpm/points/Transfer.hpp"
#include "gradmpm/solver/DofMap.hpp"
#include "gradmpm/solver/SparsePattern.hpp"

namespace gradmpm {

template <int dim>
class FBarCells {
 public:
  /// Groups the points by the cell that holds them at x_n.
  FBarCells(const Grid<dim>& grid, const MaterialPoints<dim>& pts, const PointStencils<dim>& st) : cell_(pts.size()) {
    std::map<int, int> group_of_cell;
    for (int p = 0; p < pts.size(); ++p) {
      const auto c = grid.cell_of(pts.position[p]);
      const int key = c ? linear(grid, *c) : -1;
      auto [it, fresh] = group_of_cell.try_emplace(key, static_cast<int>(members_.size()));
      if (fresh) members_.emplace_back();
      cell_[p] = it->second;
      members_[it->second].push_back(p);
    }
    weight_.resize(pts.size());
    for (const auto& m : members_) {
      double v = 0.0;
      for (int q : m) v += pts.volume[q];
      for (int q : m) weight_[q] = pts.volume[q] / v;
    }
    // The nodes each cell's points touch (the tangent couples all of them).
    nodes_.resize(members_.size());
    for (std::size_t c = 0; c < members_.size(); ++c) {
      auto& n = nodes_[c];
      for (int q : members_[c])
        for (int a = 0; a < st[q].count; ++a) n.push_back(st[q].node[a]);
      std::sort(n.begin(), n.end());
      n.erase(std::unique(n.begin(), n.end()), n.end());
    }
  }

  int cell(int p) const { return cell_[p]; }
  const std::vector<std::vector<int>>& members() const { return members_; }
  const std::vector<std::vector<int>>& nodes() const { return nodes_; }
  /// w_p = v_p,n / (the cell's points' volume)
  double weight(int p) const { return weight_[p]; }

  /// dJbar of the points of `cells` (null: every cell) from their points' dJ.
  void average(const std::vector<double>& dJ, std::vector<double>& dJbar, const std::vector<int>* cells) const {
    dJbar.resize(dJ.size());
    auto one = [&](const std::vector<int>& m) {
      double s = 0.0;
      for (int q : m) s += weight_[q] * dJ[q];
      for (int q : m) dJbar[q] = s;
    };
    if (!cells)
      for (const auto& m : members_) one(m);
    else
      for (int c : *cells) one(members_[c]);
  }

  /// The cell coupling of the tangent for `cells`: K += U_c V_c^T per cell,
  /// U_c(a i) = sum_p W_p G_pa,j Q_p,ij, V_c(b k) = sum_q beta_q G_qb,k over the cell's
  /// points, beta_q = w_q dJ_q / dJbar; G, W and Q of the cells' points (grads, weights, Q).
  /// Axisymmetric (`hoop`: each point's N_a / r): the hoop entries too, U(a r) +=
  /// W hoop_a Q_thetatheta and V(b r) += beta hoop_b.
  template <class Gradients, class Hoop = std::vector<std::array<double, 1>>>
  void add_coupling(SparseMatrix& K, const std::vector<int>& cells, const PointStencils<dim>& st, const DofMap& dofs,
                    const Gradients& grads, const std::vector<double>& weights, const std::vector<Mat3>& Q,
                    const std::vector<double>& dJ, const std::vector<double>& dJbar,
                    const Hoop* hoop = nullptr) const {
    double* values = K.valuePtr();
    for (const int c : cells) {
      const auto& nodes = nodes_[c];
      const int nn = static_cast<int>(nodes.size());
      Eigen::VectorXd U = Eigen::VectorXd::Zero(nn * dim), V = Eigen::VectorXd::Zero(nn * dim);
      for (int q : members_[c]) {
        const Stencil<dim>& s = st[q];
        const double beta = weight_[q] * dJ[q] / dJbar[q];
        for (int a = 0; a < s.count; ++a) {
          const int at = static_cast<int>(std::lower_bound(nodes.begin(), nodes.end(), s.node[a]) - nodes.begin());
          for (int i = 0; i < dim; ++i) {
            double u = 0.0;
            for (int j = 0; j < dim; ++j) u += grads[q][a][j] * Q[q](i, j);
            U[at * dim + i] += weights[q] * u;
            V[at * dim + i] += beta * grads[q][a][i];
          }
          if (hoop) {
            U[at * dim] += weights[q] * (*hoop)[q][a] * Q[q](2, 2);
            V[at * dim] += beta * (*hoop)[q][a];
          }
        }
      }
      for (int b = 0; b < nn; ++b)
        for (int k = 0; k < dim; ++k) {
          const int col = dofs.dof(nodes[b], k);
          for (int a = 0; a < nn; ++a) {
            const int k0 = pattern_offset(K, dofs.dof(nodes[a], 0), col);
            for (int i = 0; i < dim; ++i) values[k0 + i] += U[a * dim + i] * V[b * dim + k];
          }
        }
    }
  }

 private:
  static int linear(const Grid<dim>& grid, const typename Grid<dim>::Index& c) {
    int k = 0;
    for (int d = dim - 1; d >= 0; --d) k = k * (grid.cells()[d] + 1) + c[d];
    return k;
  }
  std::vector<int> cell_;
  std::vector<std::vector<int>> members_, nodes_;
  std::vector<double> weight_;
};

/// A -> A - Q (x) I: the local part of the F-bar tangent at Kirchhoff stress tau; Q is
/// kept for the cell coupling (LoadStep::add_fbar_coupling). `n`: the components the
/// volume change has, dim (plane strain) or 3 (axisymmetric: with the hoop one).
template <int dim>
void fbar_local_tangent(const Mat3& tau, Eigen::Matrix<double, 9, 9>& A, Mat3& Q, int n = dim) {
  Q.setZero();
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      double trace = 0.0;
      for (int m = 0; m < n; ++m) trace += A(3 * i + j, 3 * m + m);
      Q(i, j) = trace / n - (1.0 - 1.0 / n) * tau(i, j);
      for (int k = 0; k < n; ++k) A(3 * i + j, 3 * k + k) -= Q(i, j);
    }
}

}  // namespace gradmpm
