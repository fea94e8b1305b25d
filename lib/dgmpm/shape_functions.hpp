#pragma once
// Multilinear (linear in 1D, bilinear Q1 in 2D) shape functions of one cell, in local
// coordinates xi in [0, 1]^Dim. Node a's side along axis l is bit l of a.

#include <Eigen/Core>

namespace dgmpm {

template <int Dim>
struct CellShape {
  static constexpr int nodes = 1 << Dim;
  using Vec = Eigen::Matrix<double, Dim, 1>;
  using Values = Eigen::Matrix<double, nodes, 1>;
  using Gradients = Eigen::Matrix<double, Dim, nodes>;  // column a: grad S_a in physical units

  static double factor(double xi, int side) { return side ? xi : 1.0 - xi; }

  static Values values(const Vec& xi) {
    Values s;
    for (int a = 0; a < nodes; ++a) {
      double v = 1.0;
      for (int l = 0; l < Dim; ++l) v *= factor(xi[l], (a >> l) & 1);
      s[a] = v;
    }
    return s;
  }

  // inverse_h: 1 / h per axis, taken once (+-1 / h is +-(1 / h) exactly: no division per node).
  static Gradients gradients(const Vec& xi, const Vec& inverse_h) {
    Gradients g;
    for (int a = 0; a < nodes; ++a)
      for (int l = 0; l < Dim; ++l) {
        double v = (((a >> l) & 1) ? 1.0 : -1.0) * inverse_h[l];
        for (int k = 0; k < Dim; ++k)
          if (k != l) v *= factor(xi[k], (a >> k) & 1);
        g(l, a) = v;
      }
    return g;
  }
};

}  // namespace dgmpm
