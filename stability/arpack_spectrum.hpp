#pragma once
// Largest-magnitude eigenvalues of a large sparse real operator known only through its action
// (a matrix-vector product), with ARPACK's reverse communication (dnaupd / dneupd). For the
// whole-scene analysis (docs/method.md, "Stability"), each product is one linear step of the
// solver.

#include <complex>
#include <functional>
#include <vector>

namespace dgmpm::stability {

// y = A x for vectors of the operator's size n; x and y do not alias.
using LinearOperator = std::function<void(const double* x, double* y)>;

// One-step operators of hyperbolic schemes have their eigenvalues spread along curves near the
// unit circle, where Krylov methods converge slowly. Two remedies: spectral_radius can work on
// A^k (steps_per_product = k), whose moduli |lambda|^k are far better separated, and a problem
// ARPACK cannot converge is solved densely when small enough.
struct ArpackOptions {
  int eigenvalues = 6;       // nev
  int basis_size = 0;        // ncv; 0: max(2 nev + 1, 40), at most n
  double tolerance = 1e-13;  // relative accuracy of the Ritz values (0: machine precision)
  int max_restarts = 1000;
  int dense_limit = 2000;     // n up to which a non-converged problem is solved densely
  int steps_per_product = 1;  // spectral_radius only: ARPACK sees A^k, rho = rho(A^k)^(1/k)
};

// Sorted by decreasing modulus: nev values, or nev + 1 when ARPACK keeps a conjugate pair
// together. Small operators (n <= nev + 2, below ARPACK's minimum) and those ARPACK does not
// converge on with n <= dense_limit are assembled from n products and solved densely. Throws
// std::runtime_error when ARPACK fails otherwise.
std::vector<std::complex<double>> largest_magnitude_eigenvalues(int n, const LinearOperator& apply,
                                                                const ArpackOptions& options = {});

double spectral_radius(int n, const LinearOperator& apply, const ArpackOptions& options = {});

}  // namespace dgmpm::stability
