// SPDX-License-Identifier: LGPL-2.1-or-later
#include "heights.hpp"

#include "dct.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace caustic::design {
namespace {
void remove_mean(std::vector<double>& h) {
  const double mean = std::accumulate(h.begin(), h.end(), 0.0) / static_cast<double>(h.size());
  for (double& v : h) v -= mean;
}
}  // namespace

std::vector<double> paraxial_heights(const std::vector<glm::dvec2>& lens_unit, const std::vector<glm::dvec2>& screen_unit,
                                     const std::vector<double>& psi_at_vertices, double size, double focus, double ior) {
  const double k = size * size / (focus * (ior - 1));
  std::vector<double> h(lens_unit.size());
  for (std::size_t v = 0; v < h.size(); ++v) {
    const glm::dvec2 d = lens_unit[v] - screen_unit[v];
    h[v] = k * (0.5 * glm::dot(d, d) + psi_at_vertices[v]);
  }
  remove_mean(h);
  return h;
}

void exact_slopes(FaceGrid& grid, double focus, double ior) {
  // Largest deviation refraction out of the glass can give: grazing exit.
  const double max_deviation = 0.5 * std::acos(-1.0) - std::asin(1.0 / ior);
  const double cap = std::cos(0.995 * max_deviation);
  grid.slope.resize(grid.lens.size());
  grid.tir = 0;
  for (std::size_t v = 0; v < grid.lens.size(); ++v) {
    const glm::dvec3 to{grid.screen[v] - grid.lens[v], -focus - grid.height[v]};
    glm::dvec3 t = glm::normalize(to);
    if (-t.z < cap) {
      // Tilt t back toward -z, keeping its azimuth, to the largest deviation allowed.
      ++grid.tir;
      const glm::dvec2 xy{t.x, t.y};
      const double len = glm::length(xy);
      const double sin_cap = std::sqrt(1 - cap * cap);
      t = len > 0 ? glm::dvec3(xy / len * sin_cap, -cap) : glm::dvec3(0, 0, -1);
    }
    grid.slope[v] = -glm::dvec2(t.x, t.y) / (ior + t.z);
  }
}

std::vector<double> integrate_slopes(const FaceGrid& grid) {
  const int w = grid.w;
  std::vector<double> b(grid.lens.size(), 0.0);
  // b_v = sum over neighbours w of the wanted rise e_vw from v to w.
  const auto edge = [&](std::size_t v, std::size_t u) {
    const double e = glm::dot(0.5 * (grid.slope[v] + grid.slope[u]), grid.lens[u] - grid.lens[v]);
    b[v] += e;
    b[u] -= e;
  };
  for (int j = 0; j < w; ++j)
    for (int i = 0; i < w; ++i) {
      const std::size_t v = std::size_t(j) * w + i;
      if (i + 1 < w) edge(v, v + 1);
      if (j + 1 < w) edge(v, v + w);
    }
  // Graph Laplacian sum_w (h_w - h_v) has eigenvalues -(mu_k + mu_l).
  DctSolver solver(w, [w](int k, int l) { return -(dct_mu(k, w) + dct_mu(l, w)); });
  solver.solve(b);
  remove_mean(b);
  return b;
}

SnellPasses refine_heights(FaceGrid& grid, double focus, double ior, double tolerance, int max_passes) {
  SnellPasses out;
  while (out.passes < max_passes) {
    exact_slopes(grid, focus, ior);
    auto h = integrate_slopes(grid);
    ++out.passes;
    out.last_change = 0;
    for (std::size_t v = 0; v < h.size(); ++v) out.last_change = std::max(out.last_change, std::abs(h[v] - grid.height[v]));
    grid.height = std::move(h);
    if (out.last_change < tolerance) {
      out.settled = true;
      break;
    }
  }
  // Normals must match the final heights' rays: recompute the slopes once more.
  exact_slopes(grid, focus, ior);
  return out;
}

}  // namespace caustic::design
