// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/light_grid.hpp"

#include "caustic/receivers.hpp"

#include <algorithm>
#include <cmath>
#include <thread>

namespace caustic {
namespace {

LandedVertex land(const Scene& scene, const Solid& solid, const glm::dvec3& start, double ior,
                  std::uint64_t* signature) {
  const bool point = scene.light.type == LightType::point;
  const glm::dvec3 origin = point ? scene.light.position : start;
  const glm::dvec3 dir = point ? glm::normalize(start - scene.light.position) : scene.light.direction;
  const SolidPath path = follow_solid(solid, origin, dir, ior, scene.render.fresnel, FresnelSplit::weight);
  LandedVertex v;
  v.footprint = glm::vec3(start);
  *signature = path.signature;
  if (!path.valid) return v;
  const ReceiverHit hit = first_receiver(scene, path.origin, path.dir);
  // Alone, a screen the ray misses loses it; among receivers it goes as
  // the share of its parted triangle that no surface caught.
  if (hit.index < 0 && scene.receivers.empty()) return v;
  const auto& screen = scene.screen;
  const double denom = glm::dot(path.dir, screen.normal);
  const glm::dvec3 right = screen_right(screen);
  const glm::dvec3 plane_centre = screen.center - scene.render.report_plane_distance * screen.normal;
  const glm::dvec3 on_plane =
      path.origin + (glm::dot(plane_centre - path.origin, screen.normal) / denom) * path.dir - plane_centre;
  v.screen = glm::vec2(hit.local);
  v.surface = static_cast<float>(hit.index);
  v.element = hit.element;
  v.plane = glm::vec2(glm::dot(on_plane, right), glm::dot(on_plane, screen.up));
  v.transmittance = static_cast<float>(path.transmittance);
  v.tint = glm::vec3(path.tint);
  v.valid = 1;
  return v;
}

}  // namespace

std::array<glm::dvec2, kPartedSamples> parted_samples() {
  constexpr int kSplit = 4;
  static_assert(kSplit * kSplit == kPartedSamples);
  std::array<glm::dvec2, kPartedSamples> at{};
  int k = 0;
  // Sub-triangle centroids in barycentric steps of 1/kSplit: upright ones
  // at (a + 1/3, b + 1/3), inverted ones at (a + 2/3, b + 2/3).
  for (int u = 0; u < kSplit; ++u)
    for (int v = 0; u + v < kSplit; ++v)
      for (int flip = 0; flip < 2 && (flip == 0 || u + v + 1 < kSplit); ++flip)
        at[static_cast<std::size_t>(k++)] = {(u + (flip ? 2.0 : 1.0) / 3.0) / kSplit,
                                             (v + (flip ? 2.0 : 1.0) / 3.0) / kSplit};
  return at;
}

LandedGrid trace_light_grid(const Scene& scene, const Solid& solid, double ior, int n, int threads) {
  n = std::max(n, 2);
  const Launch launch = launch_rectangle(scene, solid.centre(), solid.points());
  LandedGrid grid;
  const std::size_t count = static_cast<std::size_t>(n) * n;
  grid.vertices.resize(count);
  grid.rays = count;
  std::vector<std::uint64_t> signature(count);
  const int workers = threads > 0 ? threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  auto rows = [&](int first) {
    for (int j = first; j < n; j += workers)
      for (int i = 0; i < n; ++i) {
        const std::size_t at = static_cast<std::size_t>(j) * n + i;
        const glm::dvec3 start = launch.origin + (static_cast<double>(i) / (n - 1)) * launch.a +
                                 (static_cast<double>(j) / (n - 1)) * launch.b;
        grid.vertices[at] = land(scene, solid, start, ior, &signature[at]);
      }
  };
  std::vector<std::thread> pool;
  for (int w = 1; w < workers; ++w) pool.emplace_back(rows, w);
  rows(0);
  for (auto& t : pool) t.join();

  // Triangles whose corners took one branch are spread whole; the others
  // (a crease, the rim, TIR on some corners) are sampled finer: the centroids
  // of their subdivision (parted_samples()), each its own ray and its own point.
  auto index = [n](int i, int j) { return static_cast<unsigned>(j * n + i); };
  struct Parted {
    glm::dvec2 corner[3];  // grid coordinates (i, j)
    glm::uvec3 t;
  };
  std::vector<Parted> parted;
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const Parted cells[2] = {{{{i, j}, {i + 1, j}, {i, j + 1}}, {index(i, j), index(i + 1, j), index(i, j + 1)}},
                               {{{i + 1, j}, {i + 1, j + 1}, {i, j + 1}},
                                {index(i + 1, j), index(i + 1, j + 1), index(i, j + 1)}}};
      for (const Parted& c : cells) {
        const glm::uvec3 t = c.t;
        const float valid = grid.vertices[t.x].valid + grid.vertices[t.y].valid + grid.vertices[t.z].valid;
        if (valid == 0) continue;  // beside the solid, or lost
        const auto& a = grid.vertices[t.x];
        const bool one_surface = a.surface >= 0 && grid.vertices[t.y].surface == a.surface &&
                                 grid.vertices[t.z].surface == a.surface;
        if (valid == 3 && one_surface && signature[t.x] == signature[t.y] && signature[t.x] == signature[t.z])
          grid.triangles.push_back(t);
        else
          parted.push_back(c);
      }
    }
  grid.split = parted.size();
  constexpr int kSamples = kPartedSamples;
  const auto centroid = parted_samples();
  std::vector<LandedVertex> samples(parted.size() * kSamples);
  auto sample_rows = [&](int first) {
    std::uint64_t ignored = 0;
    for (std::size_t p = static_cast<std::size_t>(first); p < parted.size(); p += static_cast<std::size_t>(workers)) {
      const auto& c = parted[p];
      for (int k = 0; k < kSamples; ++k) {
        const glm::dvec2 b = centroid[static_cast<std::size_t>(k)];
        const glm::dvec2 g = c.corner[0] + b.x * (c.corner[1] - c.corner[0]) + b.y * (c.corner[2] - c.corner[0]);
        const glm::dvec3 start = launch.origin + (g.x / (n - 1)) * launch.a + (g.y / (n - 1)) * launch.b;
        samples[p * kSamples + static_cast<std::size_t>(k)] = land(scene, solid, start, ior, &ignored);
      }
    }
  };
  pool.clear();
  for (int w = 1; w < workers; ++w) pool.emplace_back(sample_rows, w);
  sample_rows(0);
  for (auto& t : pool) t.join();
  grid.rays += samples.size();
  // Each sample takes 1/kSamples of its triangle's flux to its own point:
  // three copies at one spot, so the splat collapses it, each carrying one
  // of the triangle's footprint corners, so the flux is the whole triangle's.
  for (std::size_t p = 0; p < parted.size(); ++p)
    for (int k = 0; k < kSamples; ++k) {
      const LandedVertex& at = samples[p * kSamples + static_cast<std::size_t>(k)];
      if (at.valid == 0) continue;
      const auto first = static_cast<unsigned>(grid.vertices.size());
      for (const unsigned foot : {parted[p].t.x, parted[p].t.y, parted[p].t.z}) {
        LandedVertex v = at;
        v.footprint = grid.vertices[foot].footprint;
        v.share = 1.0f / kSamples;
        grid.vertices.push_back(v);
      }
      grid.triangles.emplace_back(first, first + 1, first + 2);
    }
  return grid;
}

}  // namespace caustic
