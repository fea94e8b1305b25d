#pragma once
// The DGMPM operators on one particle configuration (method.md 2-3):
//   project      particles -> nodes, mass weighted: m_i q_i = sum_p S_ip m_p q_p
//   residual     r_i = sum_l K^l_ij F^s_l(q_j) + Fhat_i (pseudo-stiffness + Godunov face fluxes)
//   update       q_i += dt r_i / m_i
//   interpolate  nodes -> particles: q_p = sum_i S_ip q_i
// Time integrators (time_integration.hpp) compose these; the solver and the stability analysis
// both step through them.

#include "boundary.hpp"
#include "discretisation.hpp"
#include "grid.hpp"

#include <Eigen/Core>
#include <array>
#include <vector>

namespace dgmpm {

template <class Physics>
class DGOperator {
 public:
  static constexpr int dim = Physics::dim;
  static constexpr int npc = 1 << dim;
  static constexpr int ncomp = Physics::n_comp;
  using State = typename Physics::State;
  using NodalField = Eigen::Matrix<double, ncomp, Eigen::Dynamic>;
  using ParticleField = Eigen::Matrix<double, ncomp, Eigen::Dynamic>;
  using Disc = Discretisation<Physics>;

  DGOperator(const Grid<dim>& grid, const Disc& disc, const Boundaries<dim>& boundaries)
      : grid_(grid), disc_(disc), bc_(boundaries) {
    for (int l = 0; l < dim; ++l) {
      for (int side = 0; side < 2; ++side) {
        neighbour_[l][side].resize(grid.num_cells());
        for (int c = 0; c < grid.num_cells(); ++c)
          neighbour_[l][side][c] = grid.neighbour(c, l, side);
      }
      face_weight_[l] = 1.0;
      for (int k = 0; k < dim; ++k)
        if (k != l) face_weight_[l] *= grid.cell_size[k];
      face_weight_[l] /= npc / 2;  // lumped face integral: an equal share per face node
    }
  }

  const Grid<dim>& grid() const { return grid_; }
  const Disc& discretisation() const { return disc_; }
  int num_nodes() const { return grid_.num_nodes(); }

  void project(const ParticleField& qp, const Eigen::VectorXd& mass, NodalField& qn) const {
    qn.setZero(ncomp, num_nodes());
    for (int c = 0; c < disc_.num_cells(); ++c) {
      if (!disc_.occupied(c)) continue;
      auto block = qn.template middleCols<npc>(c * npc);
      for (int e = disc_.cell_begin(c); e < disc_.cell_end(c); ++e) {
        const int p = disc_.entry_particle(e);
        block.noalias() += (mass[p] * qp.col(p)) * disc_.entry_shape(e).transpose();
      }
      for (int a = 0; a < npc; ++a) block.col(a) *= disc_.inverse_mass(c * npc + a);
      copy_massless(c, qn);
    }
  }

  void residual(const NodalField& qn, double t, NodalField& r) const {
    r.setZero(ncomp, num_nodes());
    Eigen::Matrix<double, ncomp, npc> flux;
    for (int c = 0; c < disc_.num_cells(); ++c) {
      if (!disc_.occupied(c)) continue;
      const auto& mat = disc_.cell_material(c);
      auto q = qn.template middleCols<npc>(c * npc);
      auto rc = r.template middleCols<npc>(c * npc);
      for (int l = 0; l < dim; ++l) {
        for (int a = 0; a < npc; ++a) flux.col(a) = Physics::specific_flux(l, q.col(a), mat);
        rc.noalias() += flux * disc_.stiffness(c, l).transpose();
      }
    }
    for (int l = 0; l < dim; ++l) face_fluxes(l, qn, t, r);
  }

  // q += dt M^-1 r. A massless node's residual goes to the node standing in for it (r is
  // scratch and is modified), and it copies that node's value after the update.
  void update(NodalField& q, NodalField& r, double dt) const {
    if (disc_.has_massless_nodes())
      for (int i = 0; i < num_nodes(); ++i) {
        const int s = disc_.node_source(i);
        if (s >= 0 && s != i) r.col(s) += r.col(i);
      }
    for (int c = 0; c < disc_.num_cells(); ++c) {
      if (!disc_.occupied(c)) continue;
      for (int a = 0; a < npc; ++a) {
        const int i = c * npc + a;
        q.col(i) += (dt * disc_.inverse_mass(i)) * r.col(i);
      }
      copy_massless(c, q);
    }
  }

  void interpolate(const NodalField& qn, ParticleField& qp) const {
    for (int c = 0; c < disc_.num_cells(); ++c) {
      if (!disc_.occupied(c)) continue;
      const auto block = qn.template middleCols<npc>(c * npc);
      for (int e = disc_.cell_begin(c); e < disc_.cell_end(c); ++e)
        qp.col(disc_.entry_particle(e)).noalias() = block * disc_.entry_shape(e);
    }
  }

 private:
  void copy_massless(int c, NodalField& q) const {
    for (int a = 0; a < npc; ++a) {
      const int i = c * npc + a, s = disc_.node_source(i);
      if (s != i) q.col(i) = q.col(s);
    }
  }

  // Godunov fluxes through every face normal to `axis`. Node R of the minus cell receives
  // -F*(x_R), node L of the plus cell +F*(x_L); boundary and void neighbours act through ghosts.
  void face_fluxes(int axis, const NodalField& qn, double t, NodalField& r) const {
    const double w = face_weight_[axis];
    const int bit = 1 << axis;
    State fm, fp;
    State ghost_value;
    for (int c = 0; c < disc_.num_cells(); ++c) {
      const int n = neighbour_[axis][1][c];
      const bool here = disc_.occupied(c);
      const bool there = n >= 0 && disc_.occupied(n);
      if (here || there) {
        for (int a = 0; a < npc; ++a) {
          if (!(a & bit)) continue;
          const int im = c * npc + a;                        // plus-side node of cell c
          const int ip = n >= 0 ? n * npc + (a ^ bit) : -1;  // matching minus-side node of n
          if (here && there) {
            Physics::godunov(axis, qn.col(im), disc_.cell_material(c), qn.col(ip),
                             disc_.cell_material(n), fm, fp);
            r.col(im) -= w * fm;
            r.col(ip) += w * fp;
          } else if (here) {
            const auto& mat = disc_.cell_material(c);
            ghost_value = n < 0 ? Physics::ghost(bc_[axis][1], t, qn.col(im), mat)
                                : Physics::void_ghost(qn.col(im), mat);
            Physics::godunov(axis, qn.col(im), mat, ghost_value, mat, fm, fp);
            r.col(im) -= w * fm;
          } else {
            const auto& mat = disc_.cell_material(n);
            ghost_value = Physics::void_ghost(qn.col(ip), mat);
            Physics::godunov(axis, ghost_value, mat, qn.col(ip), mat, fm, fp);
            r.col(ip) += w * fp;
          }
        }
      }
      // Lower grid boundary of an occupied cell.
      if (here && neighbour_[axis][0][c] < 0) {
        const auto& mat = disc_.cell_material(c);
        for (int a = 0; a < npc; ++a) {
          if (a & bit) continue;
          const int ip = c * npc + a;
          ghost_value = Physics::ghost(bc_[axis][0], t, qn.col(ip), mat);
          Physics::godunov(axis, ghost_value, mat, qn.col(ip), mat, fm, fp);
          r.col(ip) += w * fp;
        }
      }
    }
  }

  const Grid<dim>& grid_;
  const Disc& disc_;
  const Boundaries<dim>& bc_;
  Eigen::Matrix<double, dim, 1> face_weight_;
  std::array<std::array<std::vector<int>, 2>, dim> neighbour_;  // grid.neighbour, tabulated
};

}  // namespace dgmpm
