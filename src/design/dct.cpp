// SPDX-License-Identifier: LGPL-2.1-or-later
#include "dct.hpp"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <numbers>
#include <stdexcept>
#include <thread>

namespace caustic::design {
namespace {
// FFTW's planner is not thread-safe; designs may run on several threads.
std::mutex planner_mutex;

// Threads for a plan of n x n: two from 256^2 on, where FFTW's own threads
// were measured to pay on two cores (a 512^2 photograph designed in 5.0 s
// instead of 6.4 s); below that, one (thread start-up dominates).
// Called with planner_mutex held.
int plan_threads(int n) {
  static const bool ready = fftw_init_threads() != 0;
  const int cores = static_cast<int>(std::thread::hardware_concurrency());
  return ready && n >= 256 ? std::clamp(cores, 1, 2) : 1;
}
}  // namespace

double dct_mu(int k, int n) { return 2.0 - 2.0 * std::cos(std::numbers::pi * k / n); }

DctSolver::DctSolver(int n, const std::function<double(int, int)>& eigenvalue) : n_(n), inverse_(std::size_t(n) * n) {
  // REDFT10 followed by REDFT01 multiplies by 2n per axis.
  const double scale = 4.0 * n * n;
  for (int k = 0; k < n; ++k)
    for (int l = 0; l < n; ++l) inverse_[std::size_t(k) * n + l] = (k || l) ? 1.0 / (eigenvalue(k, l) * scale) : 0.0;
  std::lock_guard lock(planner_mutex);
  buffer_ = fftw_alloc_real(std::size_t(n) * n);
  if (!buffer_) throw std::bad_alloc();
  fftw_plan_with_nthreads(plan_threads(n));
  forward_ = fftw_plan_r2r_2d(n, n, buffer_, buffer_, FFTW_REDFT10, FFTW_REDFT10, FFTW_ESTIMATE);
  backward_ = fftw_plan_r2r_2d(n, n, buffer_, buffer_, FFTW_REDFT01, FFTW_REDFT01, FFTW_ESTIMATE);
  if (!forward_ || !backward_) throw std::runtime_error("FFTW could not plan a " + std::to_string(n) + "^2 DCT");
}

DctSolver::~DctSolver() {
  std::lock_guard lock(planner_mutex);
  fftw_destroy_plan(forward_);
  fftw_destroy_plan(backward_);
  fftw_free(buffer_);
}

void DctSolver::solve(std::vector<double>& rhs) {
  const std::size_t count = std::size_t(n_) * n_;
  std::copy(rhs.begin(), rhs.begin() + count, buffer_);
  fftw_execute(forward_);
  for (std::size_t i = 0; i < count; ++i) buffer_[i] *= inverse_[i];
  fftw_execute(backward_);
  std::copy(buffer_, buffer_ + count, rhs.begin());
}

}  // namespace caustic::design
