// SPDX-License-Identifier: LGPL-2.1-or-later
// Solves linear systems that are diagonal in the 2-D DCT-II basis (grid
// Laplacians with Neumann boundaries and their relatives) with FFTW: one
// forward DCT-II (REDFT10), a division by the eigenvalues, one DCT-III
// (REDFT01) back.
#pragma once

#include <fftw3.h>

#include <functional>
#include <vector>

namespace caustic::design {

class DctSolver {
 public:
  /// n x n grid, row-major. `eigenvalue(k, l)` of the operator for the mode cos(pi k (i + 1/2) / n)
  /// cos(pi l (j + 1/2) / n); the (0, 0) mode is left out (zero mean), so the
  /// function is never asked for it; k indexes the row-major array's inner
  /// (fast) axis frequency only when the operator is symmetric in k and l,
  /// as every operator here is. Plans with FFTW_ESTIMATE: deterministic and
  /// cheap to plan (FFTW_MEASURE costs over a second at 513^2).
  DctSolver(int n, const std::function<double(int, int)>& eigenvalue);
  ~DctSolver();
  DctSolver(const DctSolver&) = delete;
  DctSolver& operator=(const DctSolver&) = delete;

  /// Replaces `rhs` (n * n values) by the zero-mean solution of A u = rhs.
  void solve(std::vector<double>& rhs);
  int size() const { return n_; }

 private:
  int n_;
  std::vector<double> inverse_;  ///< 1 / (eigenvalue * FFTW's scale), 0 for the mean
  double* buffer_;
  fftw_plan forward_, backward_;
};

/// mu_k = 2 - 2 cos(pi k / n): eigenvalue of the 1-D second difference
/// (Neumann, cell- or vertex-centred DCT-II modes of length n).
double dct_mu(int k, int n);

}  // namespace caustic::design
