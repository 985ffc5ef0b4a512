// SPDX-License-Identifier: LGPL-2.1-or-later
#include "cpu_setup.hpp"

#include "bands.hpp"
#include "caustic/optics.hpp"
#include "caustic/vertex_rays.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace caustic {
namespace {

// Below this many square pixels a triangle's corners are too close for a
// stable area; its flux goes to the pixel under its centroid (caustic.geom).
constexpr double kCollapsed = 1e-4;
// The largest screen-to-plane area ratio "report" gives (shaders/caustic.geom's too).
constexpr double kMaxReportRatio = 1e12;

// Triangles and vertices per core at the least: a share thinner than that
// costs more to hand over than it saves.
constexpr std::size_t kMinShare = 4096;

double signed_area(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
  const glm::dvec2 e1 = b - a, e2 = c - a;
  return 0.5 * (e1.x * e2.y - e1.y * e2.x);
}

// A surface's rectangle and its atlas tile (pixels, origin bottom left as GL counts).
// Its scale precomputed: a division per corner cost a tenth of the set-up.
// A lathe's tile is its (u, v) square: `shape` gives the world area a unit
// of it covers where a ray landed, and which landings lie on one piece.
struct Tile {
  glm::dvec2 origin, size, centre, pixels_per_world;
  const ReceiverMesh* shape;
  Tile(glm::dvec2 half, glm::dvec2 origin, glm::dvec2 size, const ReceiverMesh* shape)
      : origin(origin), size(size), centre(origin + 0.5 * size), pixels_per_world(0.5 * size / half), shape(shape) {}
  glm::dvec2 to_pixels(glm::dvec2 local) const { return centre + local * pixels_per_world; }
  glm::dvec2 world_per_pixel() const { return 1.0 / pixels_per_world; }
  double stretch(std::int32_t element) const { return shape && element >= 0 ? shape->stretch(element) : 1.0; }
  // Three landings span a triangle of the atlas only on one continuous
  // piece of it: not across a lathe's seam.
  bool continuous(std::int32_t a, std::int32_t b, std::int32_t c) const {
    return !shape || (a >= 0 && b >= 0 && c >= 0 && shape->continuous(a, b) && shape->continuous(b, c) &&
                      shape->continuous(a, c));
  }
};

class Setup {
 public:
  Setup(const Scene& scene, const Placement& placement, glm::dvec3 weight, CoverageRaster* raster, int layer,
        bool counting, const PartedRays* parted)
      : scene_(scene),
        resolution_(raster->width(), raster->height()),
        weight_(weight),
        raster_(raster),
        layer_(layer),
        parted_(parted),
        counting_(counting) {
    const int width = raster->width(), height = raster->height();
    const auto surfaces = receiving_surfaces(scene);
    const auto layout = atlas_layout(width, height, surfaces.size());
    for (std::size_t i = 0; i < surfaces.size(); ++i)
      tiles_.emplace_back(glm::dvec2(surfaces[i].width / 2, surfaces[i].height / 2),
                          glm::dvec2(layout[i].x, height - layout[i].y - layout[i].height),
                          glm::dvec2(layout[i].width, layout[i].height),
                          surfaces[i].body());
    reference_distance2_ = reference_distance2(scene, placement);
  }

  // Triangle `t` of the mesh the raster uses.
  void triangle(std::size_t t, const LandedVertex& v0, const LandedVertex& v1, const LandedVertex& v2) {
    piece(t, v0, v1, v2, nullptr, 0);
  }

  const TriangleCounts& counted() const { return counted_; }

 private:
  // Where a piece's corners lie in its mesh triangle: barycentric weights
  // of the triangle's second and third corners.
  using Corners = std::array<glm::dvec2, 3>;
  // A parted triangle is cut in four this many times where its pieces still
  // part: 16 pieces at the most, as parted_samples()' 16 rays.
  static constexpr int kCuts = 2;

  // Triangle `t`, or at `depth` > 0 its piece with corners at `uv`.
  void piece(std::size_t t, const LandedVertex& v0, const LandedVertex& v1, const LandedVertex& v2, const Corners* uv,
             int depth) {
    const bool whole = depth == 0, valid = v0.valid * v1.valid * v2.valid >= 0.5f;
    if (whole && !valid) return count(&TriangleCounts::dropped);
    // A piece's corner may be lost inside the glass (its ray reflected
    // whole): the piece parts, its Fresnel weight the landed corners'.
    const double landed = double(v0.valid) + v1.valid + v2.valid;
    const double transmittance =
        landed > 0 ? (double(v0.valid) * v0.transmittance + double(v1.valid) * v1.transmittance +
                      double(v2.valid) * v2.transmittance) / landed
                   : 0.0;
    const int surface = static_cast<int>(v0.surface);
    const Tile& tile = tiles_[std::max(surface, 0)];
    const bool together = valid && surface >= 0 && v1.surface == v0.surface && v2.surface == v0.surface &&
                          tile.continuous(v0.element, v1.element, v2.element);
    const glm::dvec2 a = tile.to_pixels(v0.screen), b = tile.to_pixels(v1.screen), c = tile.to_pixels(v2.screen);
    const double signed_pixels = signed_area(a, b, c), area_pixels = std::abs(signed_pixels);
    const glm::dvec2 wpp = tile.world_per_pixel();
    // On a lathe, the corners' triangles' mean stretch: exact when one
    // triangle holds all three, else off by their difference.
    const double stretch = together && tile.shape
                               ? (tile.stretch(v0.element) + tile.stretch(v1.element) + tile.stretch(v2.element)) / 3.0
                               : 1.0;
    const double pixel_area = wpp.x * wpp.y * stretch, screen_area = area_pixels * pixel_area;

    double flux;
    if (scene_.render.intensity == IntensityMode::report) {
      const double plane_area = std::abs(signed_area(v0.plane, v1.plane, v2.plane));
      // The area ratio, capped where the virtual plane focuses, relative to
      // the triangle: units are free, and an absolute floor (1e-12) was a
      // micrometre-wide slab's whole triangle, darkening its picture 1e5-fold.
      const double ratio = screen_area < kMaxReportRatio * plane_area ? screen_area / plane_area : kMaxReportRatio;
      flux = transmittance * ratio * screen_area;
    } else if (scene_.light.type == LightType::point) {
      flux = transmittance * reference_distance2_ *
             optics::solid_angle(scene_.light.position, v0.footprint, v1.footprint, v2.footprint);
    } else {
      const glm::dvec3 f0 = v0.footprint;
      const glm::dvec3 area_vector = 0.5 * glm::cross(glm::dvec3(v1.footprint) - f0, glm::dvec3(v2.footprint) - f0);
      flux = transmittance * std::abs(glm::dot(area_vector, scene_.light.direction));
    }
    flux *= (double(v0.share) + v1.share + v2.share) / 3.0;
    if (!together) {  // parted among the surfaces: cut up, or a third to each corner that landed
      if (!(flux > 0.0) || std::isinf(flux)) return;
      if (parted_) {
        static const Corners kWhole{glm::dvec2(0, 0), glm::dvec2(1, 0), glm::dvec2(0, 1)};
        const Corners& at = uv ? *uv : kWhole;
        return depth < kCuts ? cut(t, v0, v1, v2, at, depth) : parted_piece(t, at, flux, transmittance);
      }
      for (const LandedVertex* v : {&v0, &v1, &v2}) landed_point(*v, flux / 3.0);
      return;
    }
    const glm::dvec2 lo = glm::min(glm::min(a, b), c), hi = glm::max(glm::max(a, b), c);
    const bool offscreen = glm::any(glm::greaterThan(lo, resolution_)) || glm::any(glm::lessThan(hi, glm::dvec2(0.0)));
    const bool huge = glm::any(glm::greaterThan(hi - lo, 64.0 * resolution_));  // precision, not physics
    if (!(flux > 0.0) || std::isinf(flux) || offscreen || huge) {
      if (!(flux == 0.0) && !offscreen && whole) count(&TriangleCounts::dropped);
      return;
    }
    const glm::vec3 tint = (v0.tint + v1.tint + v2.tint) / 3.0f;
    if (whole) {
      count(&TriangleCounts::drawn);
      count(signed_pixels >= 0.0 ? &TriangleCounts::positive : &TriangleCounts::negative);
    }
    if (area_pixels < kCollapsed) {
      count(&TriangleCounts::collapsed);
      return point((a + b + c) / 3.0, flux / pixel_area, tint);
    }
    const glm::dvec3 value = flux / screen_area * glm::dvec3(tint) * weight_;
    if (whole) raster_->mesh_triangle(t, a, b, c, value, layer_);
    else raster_->loose_triangle(a, b, c, value, layer_);
  }

  // A parted triangle or piece in four, at its sides' midpoints, each
  // piece landed by its own rays: the pieces whose corners land together
  // are spread whole (the outline's light a continuous area, not points),
  // the rest cut again.
  void cut(std::size_t t, const LandedVertex& v0, const LandedVertex& v1, const LandedVertex& v2, const Corners& uv,
           int depth) {
    const Corners mid{0.5 * (uv[0] + uv[1]), 0.5 * (uv[1] + uv[2]), 0.5 * (uv[2] + uv[0])};
    const LandedVertex m01 = (*parted_)(t, mid[0]), m12 = (*parted_)(t, mid[1]), m20 = (*parted_)(t, mid[2]);
    const Corners pieces[4] = {{uv[0], mid[0], mid[2]}, {mid[0], uv[1], mid[1]}, {mid[2], mid[1], uv[2]},
                               {mid[0], mid[1], mid[2]}};
    piece(t, v0, m01, m20, &pieces[0], depth + 1);
    piece(t, m01, v1, m12, &pieces[1], depth + 1);
    piece(t, m20, m12, v2, &pieces[2], depth + 1);
    piece(t, m01, m12, m20, &pieces[3], depth + 1);
  }

  // The smallest piece that still parts: its flux where the ray through its
  // centroid lands, with that ray's Fresnel weight in place of its corners'
  // (`transmittance`, a factor of `flux`).
  void parted_piece(std::size_t t, const Corners& uv, double flux, double transmittance) {
    const LandedVertex s = (*parted_)(t, (uv[0] + uv[1] + uv[2]) / 3.0);
    if (s.valid < 0.5f || !(flux > 0.0) || !(transmittance > 0.0)) return;
    landed_point(s, flux * s.transmittance / transmittance);
  }

  void count(std::uint32_t TriangleCounts::*which) {
    if (counting_) ++(counted_.*which);
  }

  // `flux` of a parted triangle into the pixel where `v` landed, if it did.
  void landed_point(const LandedVertex& v, double flux) {
    const int own = static_cast<int>(v.surface);
    if (own < 0) return;
    const Tile& t = tiles_[static_cast<std::size_t>(own)];
    // A landing on its rectangle's far edge belongs to the tile's last pixel.
    const glm::dvec2 p = glm::min(t.to_pixels(v.screen), t.origin + t.size - 0.5);
    count(&TriangleCounts::collapsed);
    const glm::dvec2 w = t.world_per_pixel();
    point(p, flux / (w.x * w.y * t.stretch(v.element)), v.tint);
  }

  // All of `irradiance` (flux per pixel area) into the pixel under `at`.
  void point(glm::dvec2 at, double irradiance, glm::vec3 tint) {
    raster_->point(at, irradiance * glm::dvec3(tint) * weight_, layer_);
  }

  const Scene& scene_;
  glm::dvec2 resolution_;
  glm::dvec3 weight_;
  CoverageRaster* raster_;
  int layer_;
  const PartedRays* parted_;
  // Counted here, on the thread's own stack: the threads' counts side by
  // side in one vector shared a cache line that every triangle wrote.
  bool counting_;
  TriangleCounts counted_;
  std::vector<Tile> tiles_;
  double reference_distance2_ = 0;
};

// One ray of the per-vertex method, from a point of the face (world) with
// its normal, landed on the first receiver it meets.
class VertexLanding {
 public:
  VertexLanding(const Scene& scene, const Placement& placement, double ior)
      : scene_(scene),
        placement_(placement),
        ior_(ior),
        several_(receiving_surfaces(scene).size() > 1),
        right_(screen_right(scene.screen)),
        plane_center_(scene.screen.center - scene.render.report_plane_distance * scene.screen.normal) {}

  LandedVertex land(const glm::dvec3& v, const glm::dvec3& n, glm::vec3 tint) const {
    const ScreenParams& screen = scene_.screen;
    const ExitRay exit = exit_ray(scene_, placement_, ior_, v, n);
    LandedVertex r;
    r.footprint = glm::vec3(exit.footprint);
    r.transmittance = static_cast<float>(exit.transmittance);
    r.tint = tint;
    if (!exit.valid) return r;
    const ReceiverHit hit = first_receiver(scene_, exit.origin, exit.direction);
    // Alone, a screen the ray misses drops its triangles; among receivers the
    // corners that landed keep their shares.
    r.valid = hit.index >= 0 || several_ ? 1.0f : 0.0f;
    r.surface = static_cast<float>(hit.index);
    r.element = hit.element;
    if (hit.index >= 0) r.screen = glm::vec2(hit.local);
    const double along = glm::dot(plane_center_ - exit.origin, screen.normal) / glm::dot(exit.direction, screen.normal);
    const glm::dvec3 on_plane = exit.origin + along * exit.direction - plane_center_;
    r.plane = glm::vec2(glm::dot(on_plane, right_), glm::dot(on_plane, screen.up));
    return r;
  }

  // The face's point and normal from the mesh's (model space) ones.
  glm::dvec3 place(const glm::dvec3& p) const { return glm::dvec3(placement_.model * glm::dvec4(p, 1.0)); }
  glm::dvec3 turn(const glm::dvec3& n) const { return glm::normalize(placement_.rotation * n); }

 private:
  const Scene& scene_;
  const Placement& placement_;
  double ior_;
  bool several_;
  glm::dvec3 right_, plane_center_;
};

}  // namespace

std::vector<LandedVertex> land_vertices(const Scene& scene, const Placement& placement, const Mesh& mesh, double ior) {
  const VertexLanding landing(scene, placement, ior);
  const bool tinted_mesh = tinted(mesh);
  std::vector<LandedVertex> rays(mesh.positions.size());
  // Each vertex's ray is its own: a share of them a core.
  in_bands(static_cast<int>(rays.size()), static_cast<int>(kMinShare), [&](int lo, int hi) {
    for (int i = lo; i < hi; ++i) {
      const auto k = static_cast<std::size_t>(i);
      rays[k] = landing.land(landing.place(glm::dvec3(mesh.positions[k])), landing.turn(glm::dvec3(mesh.normals[k])),
                             tinted_mesh ? mesh.colours[k] : glm::vec3(1.0f));
    }
  });
  return rays;
}

PartedRays parted_rays(const Scene& scene, const Placement& placement, const Mesh& mesh, double ior) {
  const bool tinted_mesh = tinted(mesh);
  return [landing = VertexLanding(scene, placement, ior), &mesh, tinted_mesh](std::size_t t, glm::dvec2 uv) {
    const glm::uvec3 c = mesh.triangles[t];
    const auto mix = [&](const auto& values) {
      using V = glm::dvec3;
      return (1.0 - uv.x - uv.y) * V(values[c.x]) + uv.x * V(values[c.y]) + uv.y * V(values[c.z]);
    };
    return landing.land(landing.place(mix(mesh.positions)), landing.turn(mix(mesh.normals)),
                        tinted_mesh ? glm::vec3(mix(mesh.colours)) : glm::vec3(1.0f));
  };
}

void deposit_on_cpu(const std::vector<LandedVertex>& rays, const std::vector<glm::uvec3>& triangles,
                    const Scene& scene, const Placement& placement, glm::dvec3 weight, CoverageRaster* raster,
                    TriangleCounts* counts, const PartedRays* parted) {
  // A share of the triangles a core, each into its own layer of the raster.
  const int shares = static_cast<int>(std::clamp<std::size_t>(triangles.size() / kMinShare, 1, band_cores()));
  raster->use_mesh(triangles, shares);
  std::vector<TriangleCounts> counted(static_cast<std::size_t>(shares));
  const auto share = [&](int k) {
    Setup setup(scene, placement, weight, raster, k, counts != nullptr, parted);
    const std::size_t lo = triangles.size() * k / shares, hi = triangles.size() * (k + 1) / shares;
    for (std::size_t t = lo; t < hi; ++t) setup.triangle(t, rays[triangles[t].x], rays[triangles[t].y], rays[triangles[t].z]);
    counted[static_cast<std::size_t>(k)] = setup.counted();
  };
  if (shares == 1) share(0);
  else band_crew().run(shares, share);
  if (!counts) return;
  *counts = {};
  for (const TriangleCounts& c : counted) {
    counts->drawn += c.drawn, counts->dropped += c.dropped, counts->positive += c.positive;
    counts->negative += c.negative, counts->collapsed += c.collapsed;
  }
}

}  // namespace caustic
