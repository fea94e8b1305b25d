#pragma once
// Material points as contiguous arrays (structure of arrays): one column per particle.

#include <Eigen/Core>
#include <vector>

namespace dgmpm {

template <int Dim, int NComp>
struct Particles {
  Eigen::Matrix<double, Dim, Eigen::Dynamic> position;
  Eigen::VectorXd mass;
  Eigen::VectorXd volume;
  Eigen::Matrix<double, NComp, Eigen::Dynamic> state;  // specific state q^s
  std::vector<int> material;                           // index into the scene's materials
  std::vector<int> id;                                 // creation order, for stable outputs

  int size() const { return static_cast<int>(mass.size()); }

  void resize(int n) {
    position.resize(Dim, n);
    mass.resize(n);
    volume.resize(n);
    state.resize(NComp, n);
    material.resize(n);
    id.resize(n);
  }

  // The particles order[0], order[1], ... (any subset, in any order).
  Particles select(const std::vector<int>& order) const {
    Particles p;
    p.resize(static_cast<int>(order.size()));
    for (int i = 0; i < p.size(); ++i) {
      const int o = order[i];
      p.position.col(i) = position.col(o);
      p.mass[i] = mass[o];
      p.volume[i] = volume[o];
      p.state.col(i) = state.col(o);
      p.material[i] = material[o];
      p.id[i] = id[o];
    }
    return p;
  }
};

}  // namespace dgmpm
