#include "stability/arpack_spectrum.hpp"

#include <arpack/arpack.hpp>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace dgmpm::stability {
namespace {

using Complex = std::complex<double>;

void sort_by_modulus(std::vector<Complex>& values) {
  std::sort(values.begin(), values.end(),
            [](const Complex& a, const Complex& b) { return std::abs(a) > std::abs(b); });
}

std::vector<Complex> dense_eigenvalues(int n, const LinearOperator& apply) {
  Eigen::MatrixXd a(n, n);
  Eigen::VectorXd e = Eigen::VectorXd::Zero(n);
  for (int j = 0; j < n; ++j) {
    e[j] = 1.0;
    apply(e.data(), a.col(j).data());
    e[j] = 0.0;
  }
  const Eigen::VectorXcd lambda = Eigen::EigenSolver<Eigen::MatrixXd>(a, false).eigenvalues();
  std::vector<Complex> values(lambda.data(), lambda.data() + n);
  sort_by_modulus(values);
  return values;
}

}  // namespace

std::vector<Complex> largest_magnitude_eigenvalues(int n, const LinearOperator& apply,
                                                   const ArpackOptions& options) {
  const int nev = options.eigenvalues;
  if (n < 1 || nev < 1) throw std::invalid_argument("largest_magnitude_eigenvalues: empty problem");
  // dnaupd needs nev + 2 <= ncv <= n.
  if (n <= nev + 2) {
    auto values = dense_eigenvalues(n, apply);
    values.resize(std::min<std::size_t>(values.size(), nev));
    return values;
  }
  const int ncv = std::min(n, options.basis_size > 0 ? std::max(options.basis_size, nev + 2)
                                                     : std::max(2 * nev + 1, 40));
  const int lworkl = 3 * ncv * ncv + 6 * ncv;
  std::vector<double> resid(n), v(static_cast<std::size_t>(n) * ncv), workd(3 * n), workl(lworkl);
  a_int iparam[11] = {}, ipntr[14] = {};
  iparam[0] = 1;  // exact shifts
  iparam[2] = options.max_restarts;
  iparam[6] = 1;            // mode 1: A x = lambda x
  a_int ido = 0, info = 0;  // info 0: ARPACK's own random start vector
  for (;;) {
    arpack::naupd(ido, arpack::bmat::identity, n, arpack::which::largest_magnitude, nev,
                  options.tolerance, resid.data(), ncv, v.data(), n, iparam, ipntr, workd.data(),
                  workl.data(), lworkl, info);
    if (ido != -1 && ido != 1) break;
    apply(&workd[ipntr[0] - 1], &workd[ipntr[1] - 1]);  // ipntr is 1-based (Fortran)
  }
  if (info == 1 && n <= options.dense_limit) {
    auto values = dense_eigenvalues(n, apply);
    values.resize(nev);
    return values;
  }
  if (info == 1)
    throw std::runtime_error("ARPACK dnaupd did not converge in " +
                             std::to_string(options.max_restarts) + " restarts (" +
                             std::to_string(iparam[4]) + " of " + std::to_string(nev) +
                             " eigenvalues converged)");
  if (info != 0) throw std::runtime_error("ARPACK dnaupd failed, info = " + std::to_string(info));

  std::vector<double> dr(nev + 1), di(nev + 1), workev(3 * ncv);
  std::vector<double> z(static_cast<std::size_t>(n) * (nev + 1));
  std::vector<a_int> select(ncv);
  a_int info_eupd = 0;
  arpack::neupd(false, arpack::howmny::ritz_vectors, select.data(), dr.data(), di.data(), z.data(),
                n, 0.0, 0.0, workev.data(), arpack::bmat::identity, n,
                arpack::which::largest_magnitude, nev, options.tolerance, resid.data(), ncv,
                v.data(), n, iparam, ipntr, workd.data(), workl.data(), lworkl, info_eupd);
  if (info_eupd != 0)
    throw std::runtime_error("ARPACK dneupd failed, info = " + std::to_string(info_eupd));
  std::vector<Complex> values;
  for (int k = 0; k < iparam[4]; ++k) values.emplace_back(dr[k], di[k]);
  sort_by_modulus(values);
  return values;
}

double spectral_radius(int n, const LinearOperator& apply, const ArpackOptions& options) {
  const int k = std::max(1, options.steps_per_product);
  if (k == 1) {
    const auto values = largest_magnitude_eigenvalues(n, apply, options);
    return values.empty() ? 0.0 : std::abs(values.front());
  }
  std::vector<double> a(n), b(n);
  const LinearOperator power = [&](const double* x, double* y) {
    const double* in = x;
    for (int step = 0; step < k; ++step) {  // alternate buffers, the last product into y
      double* out = step == k - 1 ? y : (step % 2 ? b.data() : a.data());
      apply(in, out);
      in = out;
    }
  };
  const auto values = largest_magnitude_eigenvalues(n, power, options);
  return values.empty() ? 0.0 : std::pow(std::abs(values.front()), 1.0 / k);
}

}  // namespace dgmpm::stability
