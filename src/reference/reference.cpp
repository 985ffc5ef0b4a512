// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/reference.hpp"

#include "caustic/optics.hpp"
#include "caustic/spectral.hpp"
#include "caustic/embree_mesh.hpp"
#include "caustic/launch.hpp"
#include "caustic/receivers.hpp"
#include "caustic/solid_path.hpp"


#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <thread>

namespace caustic {
namespace {

using optics::Vec3;

// The slab's hull as the light sees it: its caustic face, the flat face
// above it, and where the ray that reaches each vertex entered the flat face
// (up the refracted direction, which slants under oblique light: without it
// the launch would miss the slab's leading edge).
std::vector<Vec3> slab_points(const Scene& scene, const Geometry& geo, const Mesh& mesh, const Placement& p) {
  std::vector<Vec3> corners;
  const bool refractive = scene.object.material == Material::refractive;
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const Vec3 w = geo.world(i);
    corners.push_back(w);
    if (scene.object.shape == Shape::surface) continue;  // the light meets the surface alone
    corners.push_back(onto_flat_face(p, w));  // the flat face above
    const Vec3 incoming = scene.light.type == LightType::point ? glm::normalize(w - scene.light.position)
                                                               : scene.light.direction;
    if (!refractive || glm::dot(incoming, p.flat_normal) >= 0) continue;
    const auto in = optics::refract(incoming, p.flat_normal, 1.0 / scene.object.ior);
    if (!in) continue;
    const double up = glm::dot(in->direction, p.flat_normal);
    if (up < -1e-9) corners.push_back(w + ((p.flat_offset - glm::dot(w, p.flat_normal)) / up) * in->direction);
  }
  return corners;
}

struct Photon {
  Vec3 origin, dir;
  double flux;
  Vec3 tint{1.0};  // what the face's colour let through, per channel
};

// Follows one photon through the object; returns false when it never
// reaches the screen (missed the object, TIR, wrong side).
bool follow(const Scene& scene, const Geometry& geo, const Placement& p, Photon& ph) {
  using namespace optics;
  const double n = scene.object.ior;
  const bool fresnel = scene.render.fresnel;
  const Plane flat{p.flat_normal, p.flat_offset};
  Geometry::Hit hit;
  if (scene.object.material == Material::reflective) {
    if (!geo.intersect(ph.origin, ph.dir, 0.0, &hit)) return false;
    ph.dir = glm::normalize(reflect(ph.dir, face_against(hit.normal, ph.dir)));
    ph.origin = hit.point;
    ph.tint = hit.tint;
    return true;
  }
  // A surface has no flat face: the light meets the surface first, whichever side.
  const bool surface = scene.object.shape == Shape::surface;
  const bool flat_first = !surface && glm::dot(ph.dir, flat.normal) < 0.0 && flat.signed_distance(ph.origin) > 0.0;
  if (flat_first) {
    const double t = -flat.signed_distance(ph.origin) / glm::dot(ph.dir, flat.normal);
    const Vec3 entry = ph.origin + t * ph.dir;
    const auto in = refract(ph.dir, face_against(flat.normal, ph.dir), 1.0 / n);
    if (!in) return false;
    if (fresnel) ph.flux *= fresnel_transmittance(in->cos_i, 1.0, n);
    if (!geo.intersect(entry, in->direction, 0.0, &hit)) return false;  // passed beside the caustic face
    const auto out = refract(in->direction, face_against(hit.normal, in->direction), n);
    if (!out) return false;  // TIR: dropped, as the engine does
    if (fresnel) ph.flux *= fresnel_transmittance(out->cos_i, n, 1.0);
    ph.origin = hit.point;
    ph.dir = out->direction;
    ph.tint = hit.tint;
    return true;
  }
  if (!geo.intersect(ph.origin, ph.dir, 0.0, &hit)) return false;
  const auto in = refract(ph.dir, face_against(hit.normal, ph.dir), 1.0 / n);
  if (!in) return false;
  if (fresnel) ph.flux *= fresnel_transmittance(in->cos_i, 1.0, n);
  ph.tint = hit.tint;
  if (surface) {  // into the medium the screen lies in
    ph.origin = hit.point;
    ph.dir = in->direction;
    return true;
  }
  const double toward = glm::dot(in->direction, flat.normal);
  if (!(toward > 1e-9)) return false;
  const Vec3 exit = hit.point + (-flat.signed_distance(hit.point) / toward) * in->direction;
  const auto out = refract(in->direction, face_against(flat.normal, in->direction), n);
  if (!out) return false;
  if (fresnel) ph.flux *= fresnel_transmittance(out->cos_i, n, 1.0);
  ph.origin = exit;
  ph.dir = out->direction;
  return true;
}

// One wavelength (or a grey frame): the scene's object.ior throughout. A
// tinted face gives an RGB result (and its luminance as the image).
ReferenceResult trace_grey(const Scene& scene, const Mesh& mesh, const ReferenceOptions& options) {
  const Placement placement = place_object(scene.object, mesh);
  check_geometry(scene, mesh, placement);
  const bool solid = scene.object.shape == Shape::solid;
  if (solid) check_closed(mesh);
  const auto start = std::chrono::steady_clock::now();
  // A solid photon meets its faces in any order, splitting at each by
  // Fresnel's odds (caustic/solid_path.hpp); a slab's meets two in turn.
  const std::optional<Solid> body = solid ? std::optional<Solid>(std::in_place, mesh, placement) : std::nullopt;
  const std::optional<Geometry> face = solid ? std::nullopt : std::optional<Geometry>(std::in_place, mesh, placement);
  const Launch launch = solid ? launch_rectangle(scene, body->centre(), body->points())
                              : launch_rectangle(scene, placement.center, slab_points(scene, *face, mesh, placement));
  const auto strata = static_cast<std::uint64_t>(std::ceil(std::sqrt(static_cast<double>(std::max<std::uint64_t>(options.photons, 1)))));
  const int width = scene.render.width, height = scene.render.height;
  const auto surfaces = receiving_surfaces(scene);
  const auto atlas = atlas_layout(width, height, surfaces.size());
  std::vector<double> pixel_area;
  for (std::size_t i = 0; i < surfaces.size(); ++i)
    pixel_area.push_back((surfaces[i].width / atlas[i].width) * (surfaces[i].height / atlas[i].height));
  const double cell_area = glm::length(glm::cross(launch.a, launch.b)) / static_cast<double>(strata * strata);
  const bool point = scene.light.type == LightType::point;
  const double r_ref2 = point ? glm::dot(scene.light.position - placement.center, scene.light.position - placement.center) : 1.0;

  // Each thread sums into an image of its own: more threads than cores
  // would buy no speed for their memory (64 at 2048² once took 2.3 GB).
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int threads = options.threads > 0 ? std::min(options.threads, cores) : cores;
  const std::size_t channels = tinted(mesh) ? 3 : 1;
  std::vector<std::vector<double>> tiles(static_cast<std::size_t>(threads),
                                         std::vector<double>(channels * width * height, 0.0));
  std::atomic<std::uint64_t> rows_done{0}, landed{0};
  auto work = [&](int worker) {
    auto& tile = tiles[static_cast<std::size_t>(worker)];
    std::uint64_t mine = 0;
    for (std::uint64_t row = static_cast<std::uint64_t>(worker); row < strata; row += static_cast<std::uint64_t>(threads)) {
      // One generator per stratum row: the image does not depend on the thread count.
      std::mt19937_64 rng(options.seed * 0x9E3779B97F4A7C15ull + row);
      std::uniform_real_distribution<double> jitter(0.0, 1.0);
      for (std::uint64_t col = 0; col < strata; ++col) {
        const double s = (static_cast<double>(col) + jitter(rng)) / strata;
        const double t = (static_cast<double>(row) + jitter(rng)) / strata;
        const Vec3 target = launch.origin + s * launch.a + t * launch.b;
        Photon ph;
        if (point) {
          const Vec3 to = target - scene.light.position;
          const double r2 = glm::dot(to, to);
          ph.dir = to / std::sqrt(r2);
          ph.origin = scene.light.position;
          // Solid angle of the cell seen from the light, in units of E0 = I0 / r_ref^2.
          ph.flux = r_ref2 * cell_area * std::abs(glm::dot(ph.dir, launch.normal)) / r2;
        } else {
          ph.dir = scene.light.direction;
          ph.origin = target;
          ph.flux = cell_area;
        }
        if (solid) {
          const SolidPath path =
              follow_solid(*body, ph.origin, ph.dir, scene.object.ior, scene.render.fresnel, FresnelSplit::sample, &rng);
          if (!path.valid) continue;
          ph.origin = path.origin;
          ph.dir = path.dir;
          ph.tint = path.tint;
        } else if (!follow(scene, *face, placement, ph)) {
          continue;
        }
        const ReceiverHit hit = first_receiver(scene, ph.origin, ph.dir);
        if (hit.index < 0) continue;
        const auto& surface = surfaces[static_cast<std::size_t>(hit.index)];
        const AtlasTile& region = atlas[static_cast<std::size_t>(hit.index)];
        const double u = hit.local.x / surface.width + 0.5, v = 0.5 - hit.local.y / surface.height;
        if (u < 0 || u >= 1 || v < 0 || v >= 1) continue;
        const auto x = static_cast<std::size_t>(region.x + static_cast<int>(u * region.width));
        const auto y = static_cast<std::size_t>(region.y + static_cast<int>(v * region.height));
        // Irradiance: flux over the world area of a pixel of this surface's tile.
        ph.flux /= pixel_area[static_cast<std::size_t>(hit.index)] * surface_stretch(surface, hit.element);
        const std::size_t at = channels * (y * static_cast<std::size_t>(width) + x);
        for (std::size_t c = 0; c < channels; ++c) tile[at + c] += ph.flux * (channels == 3 ? ph.tint[c] : 1.0);
        ++mine;
      }
      ++rows_done;
    }
    landed += mine;
  };
  std::vector<std::thread> pool;
  std::thread reporter;
  std::atomic<bool> finished{false};
  try {
    for (int w = 1; w < threads; ++w) pool.emplace_back(work, w);
    if (options.progress)
      reporter = std::thread([&] {
        while (!finished) {
          options.progress(static_cast<double>(rows_done) / strata);
          std::this_thread::sleep_for(std::chrono::milliseconds(200));
        }
      });
  } catch (...) {  // no thread to be had: the started ones finish (a joinable thread destroyed aborts)
    for (std::thread& t : pool) t.join();
    throw;
  }
  work(0);
  for (auto& t : pool) t.join();
  finished = true;
  if (reporter.joinable()) reporter.join();
  if (options.progress) options.progress(1.0);

  ReferenceResult result;
  std::vector<float> sums(tiles[0].size());
  for (std::size_t i = 0; i < sums.size(); ++i) {
    double sum = 0;
    for (const auto& tile : tiles) sum += tile[i];  // fixed order: deterministic
    sums[i] = static_cast<float>(sum);
  }
  if (channels == 3) {
    result.rgb = RgbHdrImage{width, height, std::move(sums)};
    result.image = luminance(result.rgb);
  } else {
    result.image = HdrImage{width, height, std::move(sums)};
  }
  result.photons = strata * strata;
  result.photons_on_screen = landed;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace

ReferenceResult trace_reference(const Scene& scene, const Mesh& mesh, const ReferenceOptions& options) {
  validate_scene(scene);
  const auto passes = spectral_passes(scene, scene.render.wavelengths);
  if (passes.empty()) return trace_grey(scene, mesh, options);  // grey, or tinted in one pass
  // The photons are shared among the wavelengths: the luminance, whose
  // weights sum to one, is as noisy as a grey frame with all of them.
  ReferenceResult total;
  const std::size_t n = static_cast<std::size_t>(scene.render.width) * scene.render.height;
  total.rgb = RgbHdrImage{scene.render.width, scene.render.height, std::vector<float>(3 * n)};
  for (std::size_t k = 0; k < passes.size(); ++k) {
    Scene one = scene;
    one.object.ior = passes[k].ior;
    ReferenceOptions each = options;
    each.photons = std::max<std::uint64_t>(1, options.photons / passes.size());
    each.seed = options.seed + 7919 * k;  // independent noise per wavelength
    if (options.progress)
      each.progress = [&, k](double done) { options.progress((static_cast<double>(k) + done) / passes.size()); };
    const ReferenceResult r = trace_grey(one, mesh, each);
    const auto& w = passes[k].weight;
    // A tinted face filters each channel of the band's weight.
    const bool rgb = !r.rgb.pixels.empty();
    for (std::size_t i = 0; i < n; ++i) {
      total.rgb.pixels[3 * i] += static_cast<float>(w.r * (rgb ? r.rgb.pixels[3 * i] : r.image.pixels[i]));
      total.rgb.pixels[3 * i + 1] += static_cast<float>(w.g * (rgb ? r.rgb.pixels[3 * i + 1] : r.image.pixels[i]));
      total.rgb.pixels[3 * i + 2] += static_cast<float>(w.b * (rgb ? r.rgb.pixels[3 * i + 2] : r.image.pixels[i]));
    }
    total.photons += r.photons;
    total.photons_on_screen += r.photons_on_screen;
    total.seconds += r.seconds;
  }
  total.image = luminance(total.rgb);
  total.wavelengths = static_cast<int>(passes.size());
  return total;
}

}  // namespace caustic
