// SPDX-License-Identifier: LGPL-2.1-or-later
#include "transport.hpp"

#include "dct.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>

namespace caustic::design {
namespace {

std::size_t at(int n, int i, int j) { return std::size_t(j) * n + i; }
int mirror(int i, int n) { return i < 0 ? 0 : (i >= n ? n - 1 : i); }

double cross(glm::dvec2 a, glm::dvec2 b) { return a.x * b.y - a.y * b.x; }

// Real roots of c0 + c1 a + c2 a^2 + c3 a^3 (c3 != 0 or lower degree).
std::vector<double> real_roots(double c0, double c1, double c2, double c3) {
  const double scale = std::max({std::abs(c0), std::abs(c1), std::abs(c2), std::abs(c3)});
  if (scale == 0) return {};
  if (std::abs(c3) < 1e-14 * scale) {
    if (std::abs(c2) < 1e-14 * scale) return std::abs(c1) > 0 ? std::vector<double>{-c0 / c1} : std::vector<double>{};
    const double d = c1 * c1 - 4 * c2 * c0;
    if (d < 0) return {};
    return {(-c1 + std::sqrt(d)) / (2 * c2), (-c1 - std::sqrt(d)) / (2 * c2)};
  }
  // Depressed cubic t^3 + p t + q with a = t - b / 3.
  const double b = c2 / c3, c = c1 / c3, d = c0 / c3;
  const double p = c - b * b / 3, q = 2 * b * b * b / 27 - b * c / 3 + d;
  const double disc = q * q / 4 + p * p * p / 27;
  std::vector<double> roots;
  if (disc > 0) {
    const double s = std::sqrt(disc);
    roots.push_back(std::cbrt(-q / 2 + s) + std::cbrt(-q / 2 - s));
  } else {
    const double r = std::sqrt(std::max(-p / 3, 0.0));
    const double phi = r > 0 ? std::acos(std::clamp(-q / (2 * r * r * r), -1.0, 1.0)) : 0.0;
    for (int k = 0; k < 3; ++k) roots.push_back(2 * r * std::cos((phi - 2 * std::numbers::pi * k) / 3));
  }
  for (double& t : roots) t -= b / 3;
  return roots;
}

// Exact line search. Quad areas are quadratic in the step a along the
// direction's displacement, so each residual is r0 + a r1 + a^2 r2 and
// sum r^2 is a quartic in a: its global minimum is at a root of the cubic
// derivative. Negative areas along the way are allowed (the quartic does
// not care); only the end point matters.
double best_step(int n, const std::vector<glm::dvec2>& x, const std::vector<glm::dvec2>& dx,
                 const std::vector<double>& mass) {
  double s[5] = {0, 0, 0, 0, 0};  // coefficients of sum r^2 in a^0..a^4
  const int w = n + 1;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const std::size_t v00 = std::size_t(j) * w + i, v10 = v00 + 1, v01 = v00 + w, v11 = v01 + 1;
      const glm::dvec2 a = x[v11] - x[v00], b = dx[v11] - dx[v00], c = x[v01] - x[v10], e = dx[v01] - dx[v10];
      const double r0 = 0.5 * cross(a, c) - mass[at(n, i, j)];
      const double r1 = 0.5 * (cross(a, e) + cross(b, c)), r2 = 0.5 * cross(b, e);
      s[0] += r0 * r0;
      s[1] += 2 * r0 * r1;
      s[2] += r1 * r1 + 2 * r0 * r2;
      s[3] += 2 * r1 * r2;
      s[4] += r2 * r2;
    }
  const auto f = [&](double a) { return s[0] + a * (s[1] + a * (s[2] + a * (s[3] + a * s[4]))); };
  double best = 0, best_f = s[0];
  for (double a : real_roots(s[1], 2 * s[2], 3 * s[3], 4 * s[4]))
    if (std::isfinite(a) && f(a) < best_f) best = a, best_f = f(a);
  return best;
}

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  return std::inner_product(a.begin(), a.end(), b.begin(), 0.0);
}

}  // namespace

void gradient_points(int n, const std::vector<double>& psi, std::vector<glm::dvec2>& out) {
  const int w = n + 1;
  out.resize(std::size_t(w) * w);
  const double scale = 0.5 * n;  // 1 / (2 h)
  for (int j = 0; j <= n; ++j) {
    const int j0 = mirror(j - 1, n), j1 = mirror(j, n);
    const double* row0 = &psi[at(n, 0, j0)];
    const double* row1 = &psi[at(n, 0, j1)];
    for (int i = 0; i <= n; ++i) {
      const int i0 = mirror(i - 1, n), i1 = mirror(i, n);
      const double p00 = row0[i0], p10 = row0[i1], p01 = row1[i0], p11 = row1[i1];
      // Mirroring makes the normal component vanish on the border exactly.
      out[std::size_t(j) * w + i] = {(p10 + p11 - p00 - p01) * scale, (p01 + p11 - p00 - p10) * scale};
    }
  }
}

std::vector<glm::dvec2> lens_points(int n, const std::vector<double>& psi) {
  std::vector<glm::dvec2> out;
  gradient_points(n, psi, out);
  const int w = n + 1;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) out[std::size_t(j) * w + i] += glm::dvec2(i, j) / double(n);
  return out;
}

std::vector<double> quad_areas(int n, const std::vector<glm::dvec2>& x) {
  const int w = n + 1;
  std::vector<double> out(std::size_t(n) * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const std::size_t v00 = std::size_t(j) * w + i, v10 = v00 + 1, v01 = v00 + w, v11 = v01 + 1;
      out[at(n, i, j)] = 0.5 * cross(x[v11] - x[v00], x[v01] - x[v10]);
    }
  return out;
}

std::vector<double> vertex_mean(int n, const std::vector<double>& psi) {
  const int w = n + 1;
  std::vector<double> out(std::size_t(w) * w);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const int i0 = mirror(i - 1, n), i1 = mirror(i, n), j0 = mirror(j - 1, n), j1 = mirror(j, n);
      out[std::size_t(j) * w + i] =
          0.25 * (psi[at(n, i0, j0)] + psi[at(n, i1, j0)] + psi[at(n, i0, j1)] + psi[at(n, i1, j1)]);
    }
  return out;
}

TransportResult solve_transport(int n, const std::vector<double>& mass, const TransportOptions& options,
                                const ProgressFn& progress) {
  // The fixed operator A: the paper's Laplacian-like approximation of the
  // area Jacobian, diagonal in the DCT-II basis of the cells. Unlike the
  // exact linearisation (4 - mu instead of 4 + mu) it does not vanish on the
  // checkerboard mode, so A^-1 stays bounded.
  DctSolver solver(n, [n](int k, int l) {
    const double mk = dct_mu(k, n), ml = dct_mu(l, n);
    return (mk * (4 + ml) + (4 + mk) * ml) / 4;
  });
  const std::size_t cells = std::size_t(n) * n;
  TransportResult result;
  result.psi.assign(cells, 0.0);
  // Buffers reused across iterations (fresh 4 MB vectors per iteration cost
  // more in page faults than the arithmetic at 512^2).
  std::vector<double> target(cells), r(cells), d(cells), d_prev(cells), r_prev(cells), p(cells);
  std::vector<glm::dvec2> x, dx;
  const double max_mass = *std::max_element(mass.begin(), mass.end());
  for (int step = 1; step <= options.steps; ++step) {
    // Contrast homotopy: masses proportional to (m / max m)^t.
    const double t = static_cast<double>(step) / options.steps;
    double sum = 0;
    for (std::size_t c = 0; c < cells; ++c) sum += target[c] = std::pow(mass[c] / max_mass, t);
    for (double& m : target) m /= sum;
    const bool last = step == options.steps;
    const double tolerance = last ? options.tolerance : std::max(options.tolerance, options.step_tolerance);
    bool restart = true;
    std::vector<double> history;
    // x follows psi incrementally (lens points are linear in psi); it is
    // rebuilt exactly at each step and every 64 iterations against drift.
    for (int it = 0; it < options.max_iterations; ++it) {
      if (it % 64 == 0) x = lens_points(n, result.psi);
      double l1 = 0;
      const int w = n + 1;
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const std::size_t v00 = std::size_t(j) * w + i, v10 = v00 + 1, v01 = v00 + w, v11 = v01 + 1;
          const std::size_t c = at(n, i, j);
          l1 += std::abs(r[c] = 0.5 * cross(x[v11] - x[v00], x[v01] - x[v10]) - target[c]);
        }
      result.residual = l1;
      if (progress) progress({step, options.steps, result.iterations, l1, 0.0});
      if (l1 < tolerance) break;
      // Stalled: what is left is mostly near-checkerboard detail, which the
      // four-cell gradient can barely move (its area Jacobian nearly
      // vanishes there); more iterations buy little but time.
      history.push_back(l1);
      const std::size_t window = options.stall_window;
      if (history.size() > window && l1 > (1 - options.stall_gain) * history[history.size() - 1 - window]) break;
      // Newton-like direction d = A^-1 r, made conjugate to the last one
      // (Polak-Ribiere, clipped at 0: a restart when it stops helping).
      std::copy(r.begin(), r.end(), d.begin());
      solver.solve(d);
      double beta = 0;
      if (!restart) {
        double num = 0;
        for (std::size_t c = 0; c < cells; ++c) num += r[c] * (d[c] - d_prev[c]);
        beta = std::max(0.0, num / dot(r_prev, d_prev));
      }
      for (std::size_t c = 0; c < cells; ++c) p[c] = d[c] + beta * p[c];
      gradient_points(n, p, dx);
      const double a = best_step(n, x, dx, target);
      ++result.iterations;
      if (a == 0) {
        if (restart) break;  // even the plain Newton-like direction cannot improve: stuck
        restart = true;
        continue;
      }
      for (std::size_t c = 0; c < cells; ++c) result.psi[c] += a * p[c];
      for (std::size_t v = 0; v < x.size(); ++v) x[v] += a * dx[v];
      std::swap(d_prev, d);
      std::swap(r_prev, r);
      restart = false;
    }
  }
  result.lens = lens_points(n, result.psi);
  auto area = quad_areas(n, result.lens);
  result.residual = 0;
  for (std::size_t c = 0; c < cells; ++c) result.residual += std::abs(area[c] - mass[c]);
  return result;
}

}  // namespace caustic::design
