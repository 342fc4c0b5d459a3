#pragma once
// Material points carry all state of the analysis (paper, section 1). Stored as a
// structure of arrays so that hot loops stream through contiguous memory.
#include <Eigen/Core>
#include <algorithm>
#include <vector>

#include "gradmpm/core/Types.hpp"

namespace gradmpm {

template <int dim>
struct MaterialPoints {
  std::vector<Vec<dim>> position;           ///< current position x_p
  std::vector<Vec<dim>> original_position;  ///< X_p
  std::vector<double> volume;               ///< current volume v_p = det(F) V_p (integration weight)
  std::vector<double> original_volume;      ///< V_p
  std::vector<double> mass;                 ///< m_p = rho_0 V_p, constant
  std::vector<int> material;                ///< index into the model's material list
  std::vector<Eigen::Matrix3d> F;           ///< deformation gradient (3x3 in every dim)
  std::vector<Eigen::Matrix3d> stress;      ///< Cauchy stress
  std::vector<double> fbar_jacobian;  ///< Jbar, the volume ratio the material sees with F-bar (mpm/FBar.hpp); 1 without
  /// Every point's material history, state_stride values per point (the largest state
  /// of the model's materials; see Material::state_variables). Model::initialise_state
  /// sizes and fills it.
  std::vector<double> state;
  int state_stride = 0;
  std::vector<Vec<dim>> half_length;           ///< GIMP domain half-lengths l_p (current)
  std::vector<Vec<dim>> original_half_length;  ///< l_p0
  std::vector<Vec<dim>> force;                 ///< point load at load factor 1
  /// W_p: the work the point's stress has done since the start (LoadStep::commit adds each
  /// step's, by the trapezoid rule). W_p minus the stored elastic energy is what the point
  /// has dissipated (Model::elastic_energy).
  std::vector<double> work;
  /// A dynamic run's velocity v_p and acceleration a_p (mpm/Dynamics.hpp); zero in a
  /// quasi-static one.
  std::vector<Vec<dim>> velocity;
  std::vector<Vec<dim>> acceleration;
  /// The pore pressure p_p (compression positive; mpm/Consolidation.hpp); zero in a
  /// drained run. The total stress is stress - p I.
  std::vector<double> pore_pressure;
  /// The tangential force a frictional rigid box exerted on the point at the end of the
  /// last step (mpm/RigidContact.hpp: the stick that carries over); zero out of contact.
  std::vector<Vec<dim>> contact_shear;

  int size() const { return static_cast<int>(position.size()); }

  /// Calls f(name, array) for every array above with one entry per point (all but the
  /// state block): what a checkpoint stores (app/Checkpoint.cpp). A new array goes here too.
  template <class F>
  void for_each_array(F&& f) {
    visit_arrays(f, *this);
  }
  template <class F>
  void for_each_array(F&& f) const {
    visit_arrays(f, *this);
  }

  /// The points `ids` (in that order), every array and their state.
  MaterialPoints subset(const std::vector<int>& ids) const {
    MaterialPoints out;
    visit_arrays(
        [&](const char*, const auto& from, auto& to) {
          to.resize(ids.size());
          for (std::size_t k = 0; k < ids.size(); ++k) to[k] = from[ids[k]];
        },
        *this, out);
    out.state_stride = state_stride;
    out.state.resize(ids.size() * static_cast<std::size_t>(state_stride));
    for (std::size_t k = 0; k < ids.size(); ++k)
      std::copy(state_of(ids[k]), state_of(ids[k]) + state_stride, out.state_of(static_cast<int>(k)));
    return out;
  }
  /// Room for n points in every array (no slack from growing one point at a time).
  void reserve(std::size_t n) {
    visit_arrays([&](const char*, auto& a) { a.reserve(n); }, *this);
  }
  double* state_of(int p) { return state.data() + static_cast<std::size_t>(p) * state_stride; }
  const double* state_of(int p) const { return state.data() + static_cast<std::size_t>(p) * state_stride; }

  /// Adds an unstressed point at x with volume v; its domain is the box of half-lengths lp.
  void add(const Vec<dim>& x, double v, int mat, const Vec<dim>& lp = Vec<dim>::Zero(), double m = 0.0) {
    position.push_back(x);
    original_position.push_back(x);
    volume.push_back(v);
    original_volume.push_back(v);
    mass.push_back(m);
    material.push_back(mat);
    F.push_back(Eigen::Matrix3d::Identity());
    stress.push_back(Eigen::Matrix3d::Zero());
    fbar_jacobian.push_back(1.0);
    half_length.push_back(lp);
    original_half_length.push_back(lp);
    force.push_back(Vec<dim>::Zero());
    work.push_back(0.0);
    velocity.push_back(Vec<dim>::Zero());
    acceleration.push_back(Vec<dim>::Zero());
    pore_pressure.push_back(0.0);
    contact_shear.push_back(Vec<dim>::Zero());
  }

 private:
  /// f(name, array of each of `p`...): the same array of one or several point sets.
  template <class F, class... Self>
  static void visit_arrays(F&& f, Self&... p) {
    f("position", p.position...);
    f("original_position", p.original_position...);
    f("volume", p.volume...);
    f("original_volume", p.original_volume...);
    f("mass", p.mass...);
    f("material", p.material...);
    f("F", p.F...);
    f("stress", p.stress...);
    f("fbar_jacobian", p.fbar_jacobian...);
    f("half_length", p.half_length...);
    f("original_half_length", p.original_half_length...);
    f("force", p.force...);
    f("work", p.work...);
    f("velocity", p.velocity...);
    f("acceleration", p.acceleration...);
    f("pore_pressure", p.pore_pressure...);
    f("contact_shear", p.contact_shear...);
  }
};

}  // namespace gradmpm
