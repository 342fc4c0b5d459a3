#include "gradmpm/mpm/ImplicitGradient.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <Eigen/QR>

#include "gradmpm/grid/NodeSums.hpp"
#include "gradmpm/solver/SparsePattern.hpp"

namespace gradmpm {

namespace {
/// Below this fraction of the largest diagonal of (M + l^2 L), a node's row is left out.
constexpr double kWeakNode = 1e-8;

/// The step's stencils with those of points whose material is not regularised emptied:
/// the Helmholtz system holds the regularised material only, so its natural boundary is
/// that material's boundary. Nodes the points barely reach are left out too: a point whose
/// GIMP domain overlaps a cell by e gives its nodes N ~ e^2 and grad N ~ e, and such rows
/// (measured: a diagonal 3e-11 of the largest, off-diagonals larger than it, when the base
/// points of examples/biaxial_2d.toml bulge past the base) make the matrix numerically
/// indefinite, and CHOLMOD refuses it. Their values barely reach any point (weights below
/// 1e-4 of the largest), so kappa_bar changes by as little. The step's own cut-off
/// (drop_weak_nodes, with F-bar) does not catch them: it bounds the support sum N v, which
/// is linear in N, and that node's was above it; the diagonal here is quadratic. (A
/// distributed run's diagonal is that of every rank's points, summed at the nodes' owners.)
template <int dim>
PointStencils<dim> regularised_stencils(const Model<dim>& m, PointStencils<dim> st, const std::vector<bool>& on) {
  for (int p = 0; p < m.points.size(); ++p)
    if (!on[m.points.material[p]]) st[p].count = 0;
  const double l2 = m.regularisation.length_scale * m.regularisation.length_scale;
  Paged<double> diagonal(m.grid.num_nodes(), 0.0);  // (pages near the stencils' nodes only)
  for (int p = 0; p < m.points.size(); ++p)
    for (int a = 0; a < st[p].count; ++a)
      diagonal.at(st[p].node[a]) += m.points.volume[p] * (st[p].N[a] * st[p].N[a] + l2 * st[p].dN[a].squaredNorm());
  // (A distributed run: the totals at this rank's own and stencils' nodes, then the
  // largest over the ranks.)
  if (!m.rank_boxes.empty()) sum_at_owners(m.rank_boxes, diagonal, stencil_nodes(st));
  double largest = 0.0;  // (the diagonal is not negative: the unheld nodes' zeros change nothing)
  diagonal.for_each_held([&](int, double v) { largest = std::max(largest, v); });
  if (!m.rank_boxes.empty()) ranks::max(&largest, 1);
  const double weak = kWeakNode * largest;
  drop_nodes(st, [&](int node) { return diagonal[node] < weak; });
  return st;
}
template <class Slots>
std::vector<bool> regularised_materials(const std::vector<Slots>& slots) {
  std::vector<bool> on;
  for (const auto& s : slots) on.push_back(s.nonlocal >= 0);
  return on;
}
}  // namespace

template <int dim>
typename NonlocalPlasticStrain<dim>::Slots NonlocalPlasticStrain<dim>::slots_of(const Material& mat) {
  Slots s;
  int offset = 0;
  for (const auto& v : mat.state_variables()) {
    if (v.name == "eps_p") s.kappa = offset;
    if (v.name == "eps_p_nonlocal") s.nonlocal = offset;
    offset += v.size();
  }
  if (s.kappa < 0) s.nonlocal = -1;
  return s;
}

template <int dim>
bool NonlocalPlasticStrain<dim>::applies(const Model<dim>& m) {
  return std::any_of(m.materials.begin(), m.materials.end(),
                     [](const auto& mat) { return slots_of(*mat).nonlocal >= 0; });
}

template <int dim>
NonlocalPlasticStrain<dim>::NonlocalPlasticStrain(const Model<dim>& m, const PointStencils<dim>& stencils,
                                                  const LinearSolverSettings& solver)
    : model_(m),
      slots_([&] {
        std::vector<Slots> s;
        for (const auto& mat : m.materials) s.push_back(slots_of(*mat));
        return s;
      }()),
      stencils_(regularised_stencils(m, stencils, regularised_materials(slots_))),
      // (a distributed run: numbered by the nodes' owners; natural boundaries only, so a
      // rank needs no node beyond its own and its stencils')
      dofs_(stencils_, m.grid.num_nodes(), 1, m.rank_boxes, 0),
      assembler_(stencils_, m.points, dofs_, &m.grid),
      pattern_(build_rank_pattern(stencils_, dofs_)),
      smoother_(assembler_, pattern_, m.regularisation.length_scale, {}, solver, ranks::distributed()) {
  for (int p = 0; p < m.points.size(); ++p)
    if (slots_[m.points.material[p]].nonlocal >= 0) regularised_points_.push_back(p);
  counts_ = ranks::all_gather({static_cast<int>(regularised_points_.size())});
  for (int r = 0; r < ranks::rank(); ++r) offset_ += counts_[r];
}

template <int dim>
Eigen::VectorXd NonlocalPlasticStrain<dim>::over_ranks(const Eigen::VectorXd& mine) const {
  if (!ranks::distributed()) return mine;
  Eigen::VectorXd all(std::accumulate(counts_.begin(), counts_.end(), Eigen::Index(0)));
  ranks::all_gather_rows(mine.data(), counts_, all.data());
  return all;
}

template <int dim>
Eigen::VectorXd NonlocalPlasticStrain<dim>::nodal(const std::vector<double>& source) const {
  const auto& pts = model_.points;
  const std::size_t stride = pts.state_stride;
  std::vector<double> kappa(pts.size(), 0.0);
  for (int p : regularised_points_) kappa[p] = source[p * stride + slots_[pts.material[p]].kappa];
  return smoother_.smooth_point_field(kappa);
}

template <int dim>
Eigen::VectorXd NonlocalPlasticStrain<dim>::smoothed(const std::vector<double>& source) const {
  const std::vector<double> kappa_bar = assembler_.interpolate(nodal(source));
  Eigen::VectorXd out(regularised_points_.size());
  for (std::size_t i = 0; i < regularised_points_.size(); ++i) out[i] = kappa_bar[regularised_points_[i]];
  return out;
}

template <int dim>
Eigen::VectorXd NonlocalPlasticStrain<dim>::gather(const std::vector<double>& state) const {
  const std::size_t stride = model_.points.state_stride;
  Eigen::VectorXd out(regularised_points_.size());
  for (std::size_t i = 0; i < regularised_points_.size(); ++i) {
    const int p = regularised_points_[i];
    out[i] = state[p * stride + slots_[model_.points.material[p]].nonlocal];
  }
  return out;
}

template <int dim>
void NonlocalPlasticStrain<dim>::scatter(const Eigen::VectorXd& kappa_bar, std::vector<double>& state) const {
  const std::size_t stride = model_.points.state_stride;
  for (std::size_t i = 0; i < regularised_points_.size(); ++i) {
    const int p = regularised_points_[i];
    state[p * stride + slots_[model_.points.material[p]].nonlocal] = kappa_bar[i];
  }
}

template <int dim>
void NonlocalPlasticStrain<dim>::smooth(const std::vector<double>& source, std::vector<double>& target) const {
  scatter(smoothed(source), target);
}

template <int dim>
double NonlocalPlasticStrain<dim>::iterate(const std::vector<double>& source, std::vector<double>& target) {
  // Over every rank's regularised points, so that every rank finds the same combination.
  const Eigen::VectorXd x = over_ranks(gather(target)), g = over_ranks(smoothed(source)), f = g - x;
  Eigen::VectorXd next = g;
  if (x_prev_.size() > 0) {
    dx_.push_back(x - x_prev_);
    df_.push_back(f - f_prev_);
    if (static_cast<int>(dx_.size()) > kDepth) {
      dx_.erase(dx_.begin());
      df_.erase(df_.begin());
    }
    // gamma = argmin |f - dF gamma|; x_next = g - (dX + dF) gamma
    Eigen::MatrixXd dF(f.size(), df_.size());
    for (std::size_t j = 0; j < df_.size(); ++j) dF.col(j) = df_[j];
    const Eigen::VectorXd gamma = dF.colPivHouseholderQr().solve(f);
    for (std::size_t j = 0; j < df_.size(); ++j) next -= gamma[j] * (dx_[j] + df_[j]);
  }
  x_prev_ = x;
  f_prev_ = f;
  scatter(next.segment(offset_, static_cast<Eigen::Index>(regularised_points_.size())), target);
  if (next.size() == 0) return 0.0;
  return (next - x).lpNorm<Eigen::Infinity>() / std::max(next.lpNorm<Eigen::Infinity>(), 1e-300);
}

template class NonlocalPlasticStrain<1>;
template class NonlocalPlasticStrain<2>;
template class NonlocalPlasticStrain<3>;

}  // namespace gradmpm
